"""RC input of an ArduCopter-faced vehicle as a pymavlink script sends it: the vehicle boots in
STABILIZE, RC_CHANNELS shows SITL's receiver and each RC_CHANNELS_OVERRIDE, arming in STABILIZE
follows Copter's throttle rule, and an overridden throttle flies ALT_HOLD (1900 climbs, 1500
holds). Judged from HEARTBEAT, RC_CHANNELS, STATUSTEXT and GLOBAL_POSITION_INT on the default
configuration (realistic sensors)."""
import time

from test_ardupilot_pymavlink import ARDUPILOT, recv, relative_alt_m, wait_armable

from rotorpilot_gcs import mavlink

RELEASE, KEEP = 0, 65535  # channels 1-8 of RC_CHANNELS_OVERRIDE


def override(conn, throttle, roll=KEEP):
    """RC_CHANNELS_OVERRIDE of the roll and throttle channels (1 and 3), the others untouched."""
    chans = [roll, KEEP, throttle, KEEP, KEEP, KEEP, KEEP, KEEP]
    conn.mav.rc_channels_override_send(conn.target_system, conn.target_component, *chans)


def alt_now_m(conn):
    """The height above home [m] the vehicle reports next, what was queued before dropped."""
    while conn.recv_match(blocking=False) is not None:
        pass
    return relative_alt_m(conn)


def hold_throttle(conn, throttle, seconds):
    """Keeps channel 3 at `throttle` [µs] for `seconds` of wall time, as a script holding a stick."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        override(conn, throttle)
        time.sleep(0.2)


@ARDUPILOT
def test_stabilize_boot_rc_channels_and_an_overridden_throttle_flying_alt_hold(autopilot_factory):
    ap = autopilot_factory(connect=False)
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0
    assert hb.custom_mode == 0, "ArduCopter boots in STABILIZE"
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 4, 1)
    rc = recv(conn, "RC_CHANNELS")
    assert (rc.chancount, rc.chan1_raw, rc.chan3_raw, rc.chan5_raw) == (16, 1500, 1000, 1800), rc
    wait_armable(conn)
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 0)

    # Throttle raised: Copter refuses to arm in STABILIZE.
    override(conn, 1500, roll=1600)
    assert recv(conn, "RC_CHANNELS", 5, lambda m: (m.chan1_raw, m.chan3_raw) == (1600, 1500))
    conn.arducopter_arm()
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_COMPONENT_ARM_DISARM)
    assert ack.result == mavlink.MAV_RESULT_FAILED
    assert recv(conn, "STATUSTEXT", 5, lambda m: m.text == "Arm: Throttle too high")

    # Released (0 on channels 1-8): back to the receiver's minimum, and the vehicle arms.
    override(conn, RELEASE, roll=RELEASE)
    assert recv(conn, "RC_CHANNELS", 5, lambda m: (m.chan1_raw, m.chan3_raw) == (1500, 1000))
    conn.arducopter_arm()
    assert recv(conn, "STATUSTEXT", 10, lambda m: m.text == "Arming motors")
    conn.motors_armed_wait()
    conn.set_mode("ALT_HOLD")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 2)
    assert relative_alt_m(conn) < 0.5, "idle throttle: still on the ground"

    # Throttle 1900 climbs; 1500 holds the height.
    deadline = time.monotonic() + 40
    while alt_now_m(conn) < 5.0:
        assert time.monotonic() < deadline, "no climb on throttle 1900"
        hold_throttle(conn, 1900, 0.5)
    assert recv(conn, "RC_CHANNELS", 5, lambda m: m.chan3_raw == 1900)
    assert recv(conn, "VFR_HUD", 5).climb > 0.3
    hold_throttle(conn, 1500, 1.0)
    held_at = alt_now_m(conn)
    hold_throttle(conn, 1500, 3.0)
    assert abs(alt_now_m(conn) - held_at) < 1.0, "mid-stick holds the height"
    hb = recv(conn, "HEARTBEAT", 5)
    assert hb.custom_mode == 2 and hb.system_status == mavlink.MAV_STATE_ACTIVE

    # The override lapses (RC_OVERRIDE_TIME): in the air the resting throttle holds.
    time.sleep(3.0)
    assert recv(conn, "RC_CHANNELS", 5, lambda m: m.chan3_raw == 1000)
    assert abs(alt_now_m(conn) - held_at) < 1.5, "no override: the vehicle holds"
    conn.set_mode("LAND")
    assert recv(conn, "STATUSTEXT", 90, lambda m: m.text == "Disarming motors")
