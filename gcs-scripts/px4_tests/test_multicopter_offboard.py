"""PX4's test_multicopter_offboard.cpp (PX4-Autopilot test/mavsdk_tests): offboard position
setpoints (take off to 2 m; a 5 m box with a climb to 4 m and yaw turns, each point reached within
0.3 m), a landing by a 1 m/s descent setpoint, the vehicle back within 2 m of home; and a flight
on attitude setpoints alone (climb 10 m on GPS altitude, pitch -20 deg for 3 s, descend)."""
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester import AutopilotTester
from .autopilot_tester_manual import AutopilotTesterManual

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.offboard import PositionNedYaw

ACCEPTANCE_RADIUS_M = 0.3


@case("Offboard takeoff and land", "[multicopter][offboard]")
async def offboard_takeoff_and_land(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.store_home()
    await tester.set_rc_loss_exception("offboard")
    await tester.arm()
    await tester.offboard_goto(PositionNedYaw(0.0, 0.0, -2.0, 0.0), ACCEPTANCE_RADIUS_M, 90)
    await tester.offboard_land()
    await tester.wait_until_disarmed(120)
    await tester.check_home_within(2.0)


@case("Offboard position control", "[multicopter][offboard]")
async def offboard_position_control(url: str = CONNECTION_URL) -> None:
    takeoff = PositionNedYaw(0.0, 0.0, -2.0, 0.0)
    points = [takeoff, PositionNedYaw(0.0, 5.0, -2.0, 180.0), PositionNedYaw(5.0, 5.0, -4.0, 180.0),
              PositionNedYaw(5.0, 0.0, -4.0, 90.0), takeoff]
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.store_home()
    await tester.set_rc_loss_exception("offboard")
    await tester.arm()
    for point in points:
        await tester.offboard_goto(point, ACCEPTANCE_RADIUS_M, 10)
    await tester.offboard_land()
    await tester.wait_until_disarmed(120)
    await tester.check_home_within(2.0)


@case("Offboard attitude control", "[multicopter][offboard_attitude]")
async def offboard_attitude_control(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterManual()
    await tester.connect(url)
    await tester.set_rc_loss_exception("offboard")
    await tester.fly_forward_in_offboard_attitude()
    await tester.wait_until_disarmed(120)
