"""PX4's test_multicopter_sih_gravity.cpp and its helper fly_stabilize_without_gps_and_measure_level_error
(PX4-Autopilot test/mavsdk_tests; [sih][gravity], a regression for PX4 issue 24299): with gravity
fusion on (EKF2_IMU_CTRL 7) and arming without GPS allowed, climb to 2 m in altitude control on the
sticks (60 s of wall time at most), drop GPS and magnetometer aiding (EKF2_GPS_CTRL 0, EKF2_MAG_TYPE 5,
both sensors failed), switch to Stabilized, shake the vehicle for six cycles of pitch, roll and
throttle blips, then hold mid-stick: over 8 s the estimated attitude must stay within 10 deg of level
and within 6 deg of the true attitude (HIL_STATE_QUATERNION asked for at 25 Hz), then land.
Nothing but the ground-truth stream needs SIH, so it runs on rotorpilot's quad_x."""
import math
import time
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester import outcome
from .autopilot_tester_manual import AutopilotTesterManual
from .autopilot_tester_raw import AutopilotTesterRaw
from .checks import check, require

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.failure import FailureType, FailureUnit
    from mavsdk.telemetry import FlightMode

MAV_CMD_SET_MESSAGE_INTERVAL, MAV_CMD_DO_SET_MODE, HIL_STATE_QUATERNION = 511, 176, 115
PX4_MAIN_MODE_STABILIZED = 7
HOVER_THROTTLE = 0.55


class AutopilotTesterGravity(AutopilotTesterManual, AutopilotTesterRaw):
    async def set_stabilized_mode(self) -> None:
        result = await self.command_long(MAV_CMD_DO_SET_MODE, (1.0, float(PX4_MAIN_MODE_STABILIZED)) + (0.0,) * 5)
        check(result == "ACCEPTED", "DO_SET_MODE Stabilized accepted", result)
        ok = await self.poll(lambda: self.latest("flight_mode") == FlightMode.STABILIZED, 5)
        check(ok, "flight mode STABILIZED within 5 s", getattr(self.latest("flight_mode"), "name", None))

    async def fly_stabilize_without_gps_and_measure_level_error(self, climb_m: float) -> float:
        truth = {"roll": math.nan, "pitch": math.nan}
        result = await self.command_long(MAV_CMD_SET_MESSAGE_INTERVAL, (float(HIL_STATE_QUATERNION), 1e6 / 25.0)
                                         + (0.0,) * 5)
        check(result == "ACCEPTED", "SET_MESSAGE_INTERVAL(HIL_STATE_QUATERNION, 25 Hz) accepted", result)

        async def ground_truth():
            async for hil in self.messages("HIL_STATE_QUATERNION"):
                w, x, y, z = hil["attitude_quaternion"]
                truth["roll"] = math.degrees(math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
                truth["pitch"] = math.degrees(math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x)))))
        self.background(ground_truth())
        self.step = "altitude control on centred sticks"
        await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        result = await outcome(self.drone.manual_control.start_altitude_control())
        check(result == "SUCCESS", "start_altitude_control() == Success", result)
        await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        check(await self.poll(self._armable, 45), "health.is_armable within 45 s", self._health_text())
        await self.arm()
        self.step = f"climbing to {climb_m} m on 0.8 throttle"
        start = time.monotonic()
        while True:
            await self.sticks(1 / 50, 0.0, 0.0, 0.8, 0.0)
            p = self.latest("position")
            if p is not None and math.isfinite(p.relative_altitude_m) and p.relative_altitude_m >= climb_m:
                break
            require(time.monotonic() - start <= 60, f"climbed to {climb_m} m within 60 s (wall)",
                    p.relative_altitude_m if p is not None else None)
        await self.set_param_int("EKF2_GPS_CTRL", 0)
        await self.set_param_int("EKF2_MAG_TYPE", 5)
        await outcome(self.drone.failure.inject(FailureUnit.SENSOR_GPS, FailureType.OFF, 0))
        await outcome(self.drone.failure.inject(FailureUnit.SENSOR_MAG, FailureType.OFF, 0))
        await self.sticks(3, 0.0, 0.0, 0.5, 0.0)
        await self.set_stabilized_mode()
        check(await self.poll(lambda: math.isfinite(truth["roll"]), 5), "ground-truth attitude within 5 s", None)
        self.step = "shaking the vehicle in Stabilized without GPS"
        for _ in range(6):
            await self.sticks(3, 0.45, 0.0, HOVER_THROTTLE, 0.0)
            await self.sticks(2, 0.0, 0.45, 0.8, 0.0)
            await self.sticks(3, -0.45, 0.0, 0.3, 0.0)
            await self.sticks(2, 0.35, -0.35, HOVER_THROTTLE, 0.0)
        self.step = "mid-stick, measuring the tilt"
        await self.sticks(3, 0.0, 0.0, HOVER_THROTTLE, 0.0)
        worst = {"roll": 0.0, "pitch": 0.0, "ekf_roll": 0.0, "ekf_pitch": 0.0, "tilt_error": 0.0}
        samples = 0
        for _ in range(8 * 50):
            await self.sticks(1 / 50, 0.0, 0.0, HOVER_THROTTLE, 0.0)
            ekf = self.latest("attitude_euler")
            if math.isfinite(truth["roll"]) and math.isfinite(truth["pitch"]):
                worst["roll"] = max(worst["roll"], abs(truth["roll"]))
                worst["pitch"] = max(worst["pitch"], abs(truth["pitch"]))
                error = math.hypot(truth["roll"] - ekf.roll_deg, truth["pitch"] - ekf.pitch_deg)
                worst["tilt_error"] = max(worst["tilt_error"], error)
                samples += 1
            worst["ekf_roll"] = max(worst["ekf_roll"], abs(ekf.roll_deg))
            worst["ekf_pitch"] = max(worst["ekf_pitch"], abs(ekf.pitch_deg))
        require(samples > 0, "ground-truth attitude samples while at mid-stick", samples)
        self.step = "landing on zero throttle"
        await self.sticks(30, 0.0, 0.0, 0.0, 0.0, stop_on_ground=True)
        check(worst["ekf_roll"] < 10, "estimated roll within 10 deg of level at mid-stick", worst["ekf_roll"])
        check(worst["ekf_pitch"] < 10, "estimated pitch within 10 deg of level at mid-stick", worst["ekf_pitch"])
        return worst["tilt_error"]


@case("Stabilize mid-stick returns to level without GPS (SIH)", "[sih][gravity]")
async def stabilize_mid_stick_returns_to_level_without_gps_sih(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterGravity()
    await tester.connect(url)
    await tester.set_param_int("EKF2_IMU_CTRL", 7)
    await tester.set_param_int("COM_ARM_WO_GPS", 1)
    tilt_error = await tester.fly_stabilize_without_gps_and_measure_level_error(2.0)
    check(tilt_error < 6.0, "true attitude within 6 deg of the estimate at mid-stick", tilt_error)
