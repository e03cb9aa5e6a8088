"""PX4's AutopilotTesterFailure (PX4-Autopilot test/mavsdk_tests/autopilot_tester_failure.cpp/.h):
the parameters of failure injection and motor-failure handling, the injection itself with the
result the case expects, and the motor outputs read from ACTUATOR_OUTPUT_STATUS."""
from __future__ import annotations

from .autopilot_tester import outcome, value_of
from .autopilot_tester_raw import AutopilotTesterRaw
from .checks import check

#: ACTUATOR_OUTPUT_STATUS bounds PX4's check uses: a stopped motor at most, a running one at least.
STOPPED_MAX, RUNNING_MIN = 901.0, 999.0


class AutopilotTesterFailure(AutopilotTesterRaw):
    async def set_param_sys_failure_en(self, value: bool) -> None:
        await self.set_param_int("SYS_FAILURE_EN", int(value))

    async def set_param_fd_act_en(self, value: bool) -> None:
        await self.set_param_int("FD_ACT_EN", int(value))

    async def set_param_mc_airmode(self, value: int) -> None:
        """PX4's legacy MC_AIRMODE (0 off, 1 roll/pitch, 2 roll/pitch/yaw) as its two parameters."""
        await self.set_param_float("MC_AIRMODE_LIM", 1.0 if value >= 1 else 0.0)
        await self.set_param_int("MC_AIRMODE_YAW", 1 if value == 2 else 0)

    async def set_param_ca_failure_mode(self, value: int) -> None:
        await self.set_param_int("CA_FAILURE_MODE", value)

    async def set_param_com_act_fail_act(self, value: int) -> None:
        await self.set_param_int("COM_ACT_FAIL_ACT", value)

    async def inject_failure(self, unit, kind, instance: int, expected: str) -> None:
        result = await outcome(self.drone.failure.inject(unit, kind, instance))
        check(result == expected, f"inject({unit.name}, {kind.name}, {instance}) == {expected}", result)

    async def enable_actuator_output_status(self) -> None:
        result = await outcome(self.drone.telemetry.set_rate_actuator_output_status(20.0))
        check(result == "SUCCESS", "set_rate_actuator_output_status(20 Hz) == Success", result)
        self.latest("actuator_output_status")

    def ensure_motors_stopped(self, stopped_mask: int, num_motors: int) -> None:
        """Motors whose bit is set in `stopped_mask` must be stopped, all others running."""
        status = self.latest("actuator_output_status")
        active = status.active if status is not None else 0
        outputs = list(status.actuator) if status is not None else []
        check(active >= num_motors, f"ACTUATOR_OUTPUT_STATUS active >= {num_motors}", active)
        for i in range(num_motors):
            value = outputs[i] if i < len(outputs) else float("nan")
            if stopped_mask & (1 << i):
                check(value <= STOPPED_MAX, f"motor {i + 1} stopped (output <= {STOPPED_MAX})", value)
            else:
                check(value >= RUNNING_MIN, f"motor {i + 1} running (output >= {RUNNING_MIN})", value)

    async def get_param_float(self, name: str):
        return await value_of(self.drone.param.get_param_float(name))
