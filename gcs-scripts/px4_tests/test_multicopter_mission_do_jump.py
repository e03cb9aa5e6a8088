"""PX4's test_multicopter_mission_do_jump.cpp (PX4-Autopilot test/mavsdk_tests): a raw mission at
15 m with 100 m legs and a DO_JUMP (item 3, back to item 1, once); with item 2 current a single
MISSION_SET_CURRENT points at the DO_JUMP itself. The vehicle must resolve the jump rather than
hang, finish the mission and disarm within 240 s."""
from . import CONNECTION_URL, case
from .autopilot_tester import MissionOptions
from .autopilot_tester_raw import AutopilotTesterRaw


@case("Fly Multicopter Mission with external set-current onto a DO_JUMP item", "[multicopter]")
async def fly_multicopter_mission_with_external_set_current_onto_a_do_jump_item(
        url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterRaw()
    await tester.connect(url)
    await tester.wait_until_ready()
    options = MissionOptions(leg_length_m=100.0, relative_altitude_m=15.0)
    jump_index = await tester.prepare_multicopter_mission_with_do_jump(options, jump_repeats=1)
    await tester.arm()
    await tester.start_and_wait_for_mission_sequence_raw(2)
    await tester.send_set_current_mission_item(jump_index)
    await tester.wait_until_disarmed(240)
