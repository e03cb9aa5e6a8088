"""PX4's test_multicopter_failure_injection.cpp (PX4-Autopilot test/mavsdk_tests): a motor failure
injected in the air must be refused (DISABLED) while SYS_FAILURE_EN is 0; on a hexarotor hovering
at 10 m, a soft motor failure (the allocator told, CA_FAILURE_MODE 1 also stopping the opposite
motor) and a hard one (SYS_FAIL_MOT_OFF 1 at boot: only that motor stops) must stop exactly the
expected motors in ACTUATOR_OUTPUT_STATUS, the altitude held within 1 m, and all motors run again
once the failure is cleared. PX4 flies the hexarotor cases on SIH's hexarotor; rotorpilot's
hexa_x (opposite of rotor i is rotor i+3) stands for it."""
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester_failure import AutopilotTesterFailure

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.failure import FailureType, FailureUnit


@case("Failure Injection - Reject mid-air when it is disabled", "[multicopter]")
async def failure_injection_reject_mid_air_when_it_is_disabled(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterFailure()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.set_param_int("SYS_FAILURE_EN", 0)
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()
    await tester.inject_failure(FailureUnit.SYSTEM_MOTOR, FailureType.OFF, 1, "DISABLED")
    await tester.execute_rtl()
    await tester.wait_until_disarmed(180)


async def _motor_failure(url, stopped_mask: int) -> None:
    altitude, altitude_tolerance, hover_speed, motors, instance = 10.0, 1.0, 1.0, 6, 1
    tester = AutopilotTesterFailure()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.set_param_sys_failure_en(True)
    await tester.set_param_mc_airmode(1)
    await tester.set_param_ca_failure_mode(1)
    await tester.set_takeoff_altitude(altitude)
    await tester.enable_actuator_output_status()
    await tester.sleep_for(1)
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()
    await tester.wait_until_altitude(altitude, 30)
    await tester.wait_until_speed_lower_than(hover_speed, 30)
    tester.start_checking_altitude(altitude_tolerance)
    await tester.inject_failure(FailureUnit.SYSTEM_MOTOR, FailureType.OFF, instance, "SUCCESS")
    await tester.sleep_for(5)
    tester.ensure_motors_stopped(stopped_mask, motors)
    await tester.inject_failure(FailureUnit.SYSTEM_MOTOR, FailureType.OK, instance, "SUCCESS")
    await tester.sleep_for(5)
    tester.ensure_motors_stopped(0, motors)
    tester.stop_checking_altitude()
    await tester.execute_rtl()
    await tester.wait_until_disarmed(180)


@case("Failure Injection - Soft motor failure removes motor and opposite from allocation",
      "[motor_failure_injection]", airframe="hexa_x")
async def failure_injection_soft_motor_failure_removes_motor_and_opposite_from_allocation(
        url: str = CONNECTION_URL) -> None:
    await _motor_failure(url, 0x9)  # motor 1 and its opposite, motor 4


@case("Failure Injection - Hard motor failure stops only the failed motor", "[motor_failure_injection_hard]",
      airframe="hexa_x", boot_params=(("SYS_FAIL_MOT_OFF", 1),))
async def failure_injection_hard_motor_failure_stops_only_the_failed_motor(url: str = CONNECTION_URL) -> None:
    await _motor_failure(url, 0x1)
