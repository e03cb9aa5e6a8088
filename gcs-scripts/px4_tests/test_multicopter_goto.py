"""PX4's test_multicopter_goto.cpp (PX4-Autopilot test/mavsdk_tests): the multicopter Goto mode
(AUTO sub mode 21) entered by DO_REPOSITION at 10 m: fly 50 m north and hold within 2 m; pause
a 200 m reposition after 3 s with a hold-here reposition (Hold, never flying back, within 15 m of
the pause point); a reposition while in Hold without the mode-change flag stays in Hold; and
DO_CHANGE_SPEED to 2 m/s mid-flight keeps the speed under 2.5 m/s."""
from . import CONNECTION_URL, case
from .autopilot_tester_goto import (
    PX4_MAIN_MODE_AUTO,
    PX4_SUB_MODE_AUTO_LOITER,
    PX4_SUB_MODE_GOTO,
    AutopilotTesterGoto,
    horizontal_distance,
)

TAKEOFF_ALTITUDE_M = 10.0


async def arm_takeoff_hold(url) -> AutopilotTesterGoto:
    tester = AutopilotTesterGoto()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.store_home()
    await tester.set_takeoff_altitude(TAKEOFF_ALTITUDE_M)
    await tester.sleep_for(1)
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()
    await tester.wait_until_altitude(TAKEOFF_ALTITUDE_M, 15, 0.5)
    await tester.sleep_for(2)  # the take-off overshoot settles
    return tester


@case("Goto: reposition on a multicopter flies to and holds at the target", "[multicopter]")
async def goto_reposition_on_a_multicopter_flies_to_and_holds_at_the_target(url: str = CONNECTION_URL) -> None:
    tester = await arm_takeoff_hold(url)
    target = (50.0, 0.0)
    await tester.command_reposition(target, TAKEOFF_ALTITUDE_M)
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_GOTO, 5)
    await tester.wait_until_reaches(target, 2.0, 60)
    await tester.check_stays_within(target, 2.0, 10)


@case("Goto: pausing mid-reposition switches to Hold near the pause point", "[multicopter]")
async def goto_pausing_mid_reposition_switches_to_hold_near_the_pause_point(url: str = CONNECTION_URL) -> None:
    tester = await arm_takeoff_hold(url)
    hold_position = tester.current_local_position()
    await tester.command_reposition((200.0, 0.0), TAKEOFF_ALTITUDE_M)
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_GOTO, 5)
    await tester.sleep_for(3)
    pause_position = tester.current_local_position()
    await tester.command_hold_here()
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_AUTO_LOITER, 5)
    distance_at_pause = horizontal_distance(pause_position, hold_position)
    await tester.check_never_reaches(hold_position, distance_at_pause - 2.0, 10)
    await tester.check_stays_within(pause_position, 15.0, 5)


@case("Goto: in-place reposition while already in Hold stays in Hold and flies there", "[multicopter]")
async def goto_in_place_reposition_while_already_in_hold_stays_in_hold_and_flies_there(
        url: str = CONNECTION_URL) -> None:
    tester = await arm_takeoff_hold(url)
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_AUTO_LOITER, 5)
    target = (30.0, 0.0)
    await tester.command_reposition(target, TAKEOFF_ALTITUDE_M, change_mode=False)
    await tester.wait_until_reaches(target, 2.0, 60)
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_AUTO_LOITER, 1)


@case("Goto: speed change while flying is applied", "[multicopter]")
async def goto_speed_change_while_flying_is_applied(url: str = CONNECTION_URL) -> None:
    tester = await arm_takeoff_hold(url)
    await tester.command_reposition((200.0, 0.0), TAKEOFF_ALTITUDE_M)
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_GOTO, 5)
    await tester.sleep_for(5)  # up to the default cruise speed
    slow = 2.0
    await tester.change_speed(slow)
    await tester.sleep_for(4)  # slowing down
    await tester.check_max_horizontal_speed(slow + 0.5, 5)
    await tester.wait_until_nav_state(PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_GOTO, 1)
