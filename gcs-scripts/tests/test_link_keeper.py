"""The library keeps the link alive by itself (its keeper thread, as MAVSDK serves its link): a
script that sleeps between calls, longer than the autopilot's data-link-loss time-out
(COM_DL_LOSS_T 10 s, with NAV_DLL_ACT = RTL so a loss would show) and far longer than the
offboard-loss one (COM_OF_LOSS_T 1 s), keeps its GCS heartbeat and its offboard setpoint stream
going: the vehicle stays in OFFBOARD on the setpoint and no failsafe runs."""
import time

import rotorpilot_gcs as gcs


def test_a_script_that_sleeps_keeps_its_link_and_its_offboard_stream(autopilot_factory):
    ap = autopilot_factory(speedup=2, params={"NAV_DLL_ACT": 2})
    ap.takeoff(3.0)
    here = ap.local_position()
    ap.set_setpoint(here.x, here.y, -3.0)
    ap.set_mode(gcs.OFFBOARD)
    boot_ms = ap.wait("ATTITUDE").time_boot_ms
    start = time.monotonic()
    time.sleep(12.0)  # no library call at all
    # Read what came meanwhile (its STATUSTEXTs are noted), up to the vehicle's present.
    ap.wait("ATTITUDE", lambda m: m.time_boot_ms > boot_ms + 2 * 11_500, timeout=30)
    beat = ap.wait_heartbeat()
    assert gcs.mode_name(beat.custom_mode) == "OFFBOARD", gcs.mode_name(beat.custom_mode)
    assert beat.base_mode & gcs.mavlink.MAV_MODE_FLAG_SAFETY_ARMED
    for lost in ("lost", "failsafe", "Failsafe"):
        assert gcs.recent_text(ap.conn, start, lost) is None, gcs.recent_text(ap.conn, start, lost)
    p = ap.local_position()
    assert abs(p.z + 3.0) < 0.5 and abs(p.x - here.x) < 1.0 and abs(p.y - here.y) < 1.0, p
