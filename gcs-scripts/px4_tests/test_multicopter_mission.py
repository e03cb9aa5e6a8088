"""PX4's test_multicopter_mission.cpp (PX4-Autopilot test/mavsdk_tests): take-off and landing, and
MAVSDK missions (a 20 m square at 10 m, a 5-point straight line) flown to the end, with RTL from
the mission or commanded, the track held within 5 m of each leg and, on the straight line with
fly-through items, the speed kept above the limit past the middle item.

The straight-line case is compiled out in PX4's newest text (its multicopter navigator stops at
each item, the comment says); its newest parameters (40 m legs, > 3.5 m/s while item 3 is current)
are kept here and the case runs.
"""
from . import CONNECTION_URL, case
from .autopilot_tester import AutopilotTester, MissionOptions


@case("Takeoff and Land", "[multicopter][vtol]")
async def takeoff_and_land(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()
    await tester.land()
    await tester.wait_until_disarmed(180)


@case("Fly square Multicopter Missions including RTL", "[multicopter]")
async def fly_square_multicopter_missions_including_rtl(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.prepare_square_mission(MissionOptions(rtl_at_end=True))
    await tester.arm()
    await tester.execute_mission()
    await tester.wait_until_disarmed(180)


@case("Fly square Multicopter Missions with manual RTL", "[multicopter]")
async def fly_square_multicopter_missions_with_manual_rtl(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.prepare_square_mission(MissionOptions(rtl_at_end=False))
    tester.check_tracks_mission(5.0)
    await tester.arm()
    await tester.execute_mission()
    await tester.wait_until_hovering()
    await tester.execute_rtl()
    await tester.wait_until_disarmed(180)


@case("Fly straight Multicopter Mission", "[multicopter]", disabled_upstream=True)
async def fly_straight_multicopter_mission(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.prepare_straight_mission(MissionOptions(rtl_at_end=False, fly_through=True, leg_length_m=40.0))
    tester.check_mission_item_speed_above(3, 3.5)
    tester.check_tracks_mission(5.0)
    await tester.arm()
    await tester.execute_mission()
    await tester.wait_until_hovering()
    await tester.execute_rtl()
    await tester.wait_until_disarmed(180)
