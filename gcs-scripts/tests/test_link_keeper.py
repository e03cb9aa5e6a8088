"""The library keeps the link alive by itself (its keeper thread, as MAVSDK serves its link): a
script that sleeps between calls, longer than the autopilot's data-link-loss time-out
(COM_DL_LOSS_T 10 s, with NAV_DLL_ACT = RTL so a loss would show) and far longer than the
offboard-loss one (COM_OF_LOSS_T 1 s), keeps its GCS heartbeat and its offboard setpoint stream
going: the vehicle stays in OFFBOARD on the setpoint and no failsafe runs."""
import time

import pytest

import rotorpilot_gcs as gcs

#: The script's sleep between two library calls [s, wall clock]: past COM_DL_LOSS_T even at 1x.
SLEEP_S = 12.0
SPEEDUP = 2


@pytest.mark.rotorpilot(speedup=SPEEDUP, params={"NAV_DLL_ACT": 2})
def test_a_script_that_sleeps_keeps_its_link_and_its_offboard_stream(vehicle):
    # The failsafes a silent ground station would trip, shorter than the sleep.
    assert vehicle.param_get("COM_DL_LOSS_T") <= 10.0 and vehicle.param_get("NAV_DLL_ACT") == 2
    assert vehicle.param_get("COM_OF_LOSS_T") <= 1.0
    vehicle.takeoff(3.0)
    here = vehicle.local_position()
    vehicle.set_setpoint(here.x, here.y, -3.0)
    vehicle.set_mode(gcs.OFFBOARD)
    boot_ms = vehicle.wait("ATTITUDE").time_boot_ms
    start = time.monotonic()
    time.sleep(SLEEP_S)  # no library call at all
    # Read what came meanwhile (as much as the socket kept), up to the vehicle's present: every
    # HEARTBEAT shows OFFBOARD and armed, and the STATUSTEXTs are noted.
    modes = []

    def caught_up(m):
        if m.get_type() == "HEARTBEAT":
            if m.get_srcComponent() != vehicle.conn.target_component:
                return False
            modes.append((gcs.mode_name(m.custom_mode), bool(m.base_mode & gcs.mavlink.MAV_MODE_FLAG_SAFETY_ARMED)))
            return False
        return m.time_boot_ms > boot_ms + SPEEDUP * (SLEEP_S - 0.5) * 1000

    vehicle.wait(["ATTITUDE", "HEARTBEAT"], caught_up, timeout=30)
    assert len(modes) >= 3, modes
    assert set(modes) == {("OFFBOARD", True)}, modes
    beat = vehicle.wait_heartbeat()
    assert gcs.mode_name(beat.custom_mode) == "OFFBOARD", gcs.mode_name(beat.custom_mode)
    assert beat.base_mode & gcs.mavlink.MAV_MODE_FLAG_SAFETY_ARMED
    for lost in ("lost", "failsafe", "Failsafe"):
        text = vehicle.recent_text(start, lost)
        assert text is None, text
    p = vehicle.local_position()
    assert abs(p.z + 3.0) < 0.5 and abs(p.x - here.x) < 1.0 and abs(p.y - here.y) < 1.0, p
