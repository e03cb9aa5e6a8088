"""PX4's test_multicopter_rtl.cpp (PX4-Autopilot test/mavsdk_tests): RTL_TYPE 6 (the closest of
home and the rally points, by time remaining) with no rally point, with one farther than home
(100 m north, 100 m west; home wins), and with one 300 m north after flying 400 m north at 20 m in
offboard (the rally point wins: land within 5 m of it, more than 20 m from home)."""
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester_rtl import AutopilotTesterRtl

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.offboard import PositionNedYaw


async def _ready(url) -> AutopilotTesterRtl:
    tester = AutopilotTesterRtl()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.store_home()
    await tester.set_rtl_type(6)
    return tester


async def _take_off(tester) -> None:
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()


@case("RTL_TYPE=6 time_remaining_s NaN with no rally points", "[multicopter]")
async def rtl_type_6_time_remaining_s_nan_with_no_rally_points(url: str = CONNECTION_URL) -> None:
    tester = await _ready(url)
    await _take_off(tester)
    await tester.execute_rtl()
    await tester.wait_until_disarmed(90)
    await tester.check_home_within(5.0)


@case("RTL_TYPE=6 time_remaining_s NaN with rally points and home is closest", "[multicopter]")
async def rtl_type_6_time_remaining_s_nan_with_rally_points_and_home_is_closest(url: str = CONNECTION_URL) -> None:
    tester = await _ready(url)
    tester.add_local_rally_point(100.0, -100.0)
    await tester.upload_rally_points()
    await _take_off(tester)
    await tester.execute_rtl()
    await tester.wait_until_disarmed(90)
    await tester.check_home_within(5.0)


@case("RTL_TYPE=6 time_remaining_s NaN with rally points and home is not closest", "[multicopter]")
async def rtl_type_6_time_remaining_s_nan_with_rally_points_and_home_is_not_closest(
        url: str = CONNECTION_URL) -> None:
    tester = await _ready(url)
    tester.add_local_rally_point(300.0, 0.0)
    await tester.upload_rally_points()
    await _take_off(tester)
    await tester.offboard_goto(PositionNedYaw(400.0, 0.0, -20.0, 0.0), 5.0, 60)
    await tester.execute_rtl()
    await tester.wait_until_disarmed(150)
    tester.check_rally_point_within(5.0)
    await tester.check_home_not_within(20.0)
