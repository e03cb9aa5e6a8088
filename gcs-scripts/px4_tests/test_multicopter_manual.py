"""PX4's test_multicopter_manual.cpp (PX4-Autopilot test/mavsdk_tests): climb, fly forward and come
down on the sticks in position and in altitude control; after the disarm the vehicle must be more
than 5 m from where it took off."""
from . import CONNECTION_URL, case
from .autopilot_tester_manual import AutopilotTesterManual


@case("Fly forward in position control", "[multicopter][vtol]")
async def fly_forward_in_position_control(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterManual()
    await tester.connect(url)
    await tester.fly_forward_in_posctl()
    await tester.wait_until_disarmed(180)
    await tester.check_home_not_within(5.0)


@case("Fly forward in altitude control", "[multicopter][vtol]")
async def fly_forward_in_altitude_control(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterManual()
    await tester.connect(url)
    await tester.fly_forward_in_altctl()
    await tester.wait_until_disarmed(180)
    await tester.check_home_not_within(5.0)
