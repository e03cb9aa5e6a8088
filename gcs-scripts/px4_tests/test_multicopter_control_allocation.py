"""PX4's test_multicopter_control_allocation.cpp (PX4-Autopilot test/mavsdk_tests), flown by PX4
on the Typhoon H480 hexarotor (configs/sitl.json's [controlallocation] model), here on
rotorpilot's hexa_x. With failure injection, motor-failure detection (FD_ACT_EN), airmode and
CA_FAILURE_MODE 1: one motor off at 10 m, then the 20 m square mission within 5 m of its legs and
4 m of altitude, then RTL home within 5 m; two opposite motors off (PX4's 1 and 2 on the Typhoon,
1 and 4 on hexa_x), mission, land; every motor off and back in turn; a motor off with
COM_ACT_FAIL_ACT 3 (RTL by itself, home within 5 m); and a motor off at 100 m with
COM_ACT_FAIL_ACT 4 (flight termination: on the ground and disarmed within 2 s plus the
free-fall time). PX4 waits the second after each injection and before arming on the host clock."""
import asyncio
import math
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester import MissionOptions
from .autopilot_tester_failure import AutopilotTesterFailure

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.failure import FailureType, FailureUnit

ALTITUDE_M, ALTITUDE_TOLERANCE_M, HOVER_SPEED_M_S = 10.0, 4.0, 1.0
#: hexa_x's motor i + 3 sits opposite motor i (PX4's Typhoon H480 numbers them in pairs, 1 and 2).
HEXA_OPPOSITE = 3
MOTOR = FailureUnit.SYSTEM_MOTOR


async def _configured(url, fail_action=None) -> AutopilotTesterFailure:
    tester = AutopilotTesterFailure()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.set_param_sys_failure_en(True)
    await tester.set_param_fd_act_en(True)
    await tester.set_param_mc_airmode(1)
    await tester.set_param_ca_failure_mode(1)
    if fail_action is not None:
        await tester.set_param_com_act_fail_act(fail_action)
    return tester


async def _mission_ready(tester) -> None:
    await tester.prepare_square_mission(MissionOptions(rtl_at_end=False, relative_altitude_m=ALTITUDE_M))
    await tester.set_takeoff_altitude(ALTITUDE_M)
    await tester.set_rtl_altitude(ALTITUDE_M)
    tester.check_tracks_mission(5.0)
    await tester.store_home()
    await asyncio.sleep(1)  # PX4: lets the take-off altitude settle in


async def _hover(tester, altitude=ALTITUDE_M, timeout_s=30, hovering=True) -> None:
    await tester.arm()
    await tester.takeoff()
    if hovering:
        await tester.wait_until_hovering()
    await tester.wait_until_altitude(altitude, timeout_s)
    await tester.wait_until_speed_lower_than(HOVER_SPEED_M_S, timeout_s)


async def _motor(tester, instance, kind=FailureType.OFF) -> None:
    await tester.inject_failure(MOTOR, kind, instance, "SUCCESS")
    await asyncio.sleep(1)


@case("Control Allocation - Remove one motor", "[controlallocation]", airframe="hexa_x")
async def control_allocation_remove_one_motor(url: str = CONNECTION_URL) -> None:
    tester = await _configured(url)
    await _mission_ready(tester)
    await _hover(tester)
    tester.start_checking_altitude(ALTITUDE_TOLERANCE_M)
    await _motor(tester, 1)
    await tester.execute_mission()
    tester.stop_checking_altitude()
    await tester.execute_rtl()
    await tester.wait_until_disarmed(180)
    await tester.check_home_within(5.0)


@case("Control Allocation - Remove two motors", "[controlallocation]", airframe="hexa_x")
async def control_allocation_remove_two_motors(url: str = CONNECTION_URL) -> None:
    tester = await _configured(url)
    await _mission_ready(tester)
    await _hover(tester)
    tester.start_checking_altitude(ALTITUDE_TOLERANCE_M)
    # PX4 removes "two motors opposite of one another on the hexa airframe", its motors 1 and 2;
    # on hexa_x (motors numbered round the ring) the motor opposite motor 1 is motor 4.
    await _motor(tester, 1)
    await _motor(tester, 1 + HEXA_OPPOSITE)
    await tester.execute_mission()
    tester.stop_checking_altitude()
    await tester.land()  # PX4: RTL would wait forever for its yaw with two motors out
    await tester.wait_until_disarmed(180)


@case("Control Allocation - Remove and restore every motor once", "[controlallocation]", airframe="hexa_x")
async def control_allocation_remove_and_restore_every_motor_once(url: str = CONNECTION_URL) -> None:
    tester = await _configured(url)
    await _mission_ready(tester)
    await _hover(tester)
    tester.start_checking_altitude(ALTITUDE_TOLERANCE_M)
    for motor in range(1, 7):
        await _motor(tester, motor)
        await _motor(tester, motor, FailureType.OK)
    await tester.execute_mission()
    tester.stop_checking_altitude()
    await tester.execute_rtl()
    await tester.wait_until_disarmed(180)
    await tester.check_home_within(5.0)


@case("Control Allocation - Return home on motor failure", "[controlallocation]", airframe="hexa_x")
async def control_allocation_return_home_on_motor_failure(url: str = CONNECTION_URL) -> None:
    tester = await _configured(url, fail_action=3)
    await tester.set_takeoff_altitude(ALTITUDE_M)
    await tester.store_home()
    await asyncio.sleep(1)
    await _hover(tester)
    await _motor(tester, 1)
    await tester.wait_until_disarmed(180)  # the RTL has to come by itself
    await tester.check_home_within(5.0)


@case("Control Allocation - Terminate on motor failure", "[controlallocation]", airframe="hexa_x")
async def control_allocation_terminate_on_motor_failure(url: str = CONNECTION_URL) -> None:
    altitude = 100.0
    tester = await _configured(url, fail_action=4)
    await tester.set_takeoff_altitude(altitude)
    await asyncio.sleep(1)
    await _hover(tester, altitude, 60, hovering=False)
    await _motor(tester, 1)
    # Only a free fall (h = g/2 t^2, g taken as 10) reaches the ground this fast.
    seconds_to_touchdown = int(2 + math.sqrt(altitude * 2 / 10.0))
    await tester.wait_until_disarmed(seconds_to_touchdown)
