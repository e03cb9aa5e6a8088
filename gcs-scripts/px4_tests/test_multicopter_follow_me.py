"""PX4's test_multicopter_follow_me.cpp (PX4-Autopilot test/mavsdk_tests): after a take-off to 10 m,
follow a target walking north at 2 m/s, streamed at 1 Hz with or without its velocity, from behind,
in front and at +-45 deg (distance 8 +- 11 m, altitude 10 +- 1.5 m); stay put (< 4 m) when only a
velocity comes; and move the follow height, distance and angle with the sticks."""
from . import CONNECTION_URL, case
from .autopilot_tester_follow_me import AutopilotTesterFollowMe

TAKEOFF_ALTITUDE_M = 10.0


async def _take_off(url) -> AutopilotTesterFollowMe:
    tester = AutopilotTesterFollowMe()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.store_home()
    await tester.arm()
    await tester.set_takeoff_altitude(TAKEOFF_ALTITUDE_M)
    await tester.takeoff()
    await tester.wait_until_hovering()
    return tester


@case("Follow target - Position streaming", "[multicopter]")
async def follow_target_position_streaming(url: str = CONNECTION_URL) -> None:
    tester = await _take_off(url)
    await tester.straight_line_test(stream_velocity=False)
    await tester.land()
    await tester.wait_until_disarmed(300)


@case("Follow target - Position and velocity streaming", "[multicopter]")
async def follow_target_position_and_velocity_streaming(url: str = CONNECTION_URL) -> None:
    tester = await _take_off(url)
    await tester.straight_line_test(stream_velocity=True)
    await tester.land()
    await tester.wait_until_disarmed(300)


@case("Follow target - Velocity streaming only", "[multicopter]")
async def follow_target_velocity_streaming_only(url: str = CONNECTION_URL) -> None:
    tester = await _take_off(url)
    await tester.stream_velocity_only()
    await tester.land()
    await tester.wait_until_disarmed(300)
    await tester.check_home_within(1.0)


@case("Follow target - RC Adjustment", "[multicopter]")
async def follow_target_rc_adjustment(url: str = CONNECTION_URL) -> None:
    tester = await _take_off(url)
    await tester.rc_adjustment_test()
    await tester.land()
    await tester.wait_until_disarmed(300)
