"""Copter's answers a pymavlink script meets on an ArduCopter-faced vehicle (docs/ardupilot.md §2):
SET_MODE answered with a COMMAND_ACK whose command is 11, LOITER chosen while disarmed before a
position and arming then refused with Copter's "PreArm: " text, DO_CHANGE_SPEED's climb speed (type
2) flown, and the GCS failsafe: "GCS Failsafe", RTL shown and the HEARTBEAT CRITICAL. Judged from
telemetry on the default configuration (realistic sensors)."""
import time

import pytest
from test_ardupilot_pymavlink import EKF_PRED_POS_HORIZ_ABS, recv, relative_alt_m, wait_armable

from rotorpilot_gcs import mavlink
from rotorpilot_gcs.link import set_heartbeats

SET_MODE_ID = 11  # ArduCopter ACKs the SET_MODE message under its message id


def set_mode(conn, number):
    """The SET_MODE message with Copter mode `number`; its COMMAND_ACK's result."""
    conn.mav.set_mode_send(conn.target_system, mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, number)
    return recv(conn, "COMMAND_ACK", 10, lambda m: m.command == SET_MODE_ID).result


def beat(conn):
    conn.mav.heartbeat_send(mavlink.MAV_TYPE_GCS, mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)


def recv_beating(conn, kinds, timeout, until):
    """`recv` while the ground station keeps sending its HEARTBEAT (every 0.5 s)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        beat(conn)
        try:
            return recv(conn, kinds, 0.5, until)
        except AssertionError:
            pass
    raise AssertionError(f"no {kinds} within {timeout} s")


@pytest.mark.rotorpilot(autopilot="ardupilot", speedup=2, params={"FS_GCS_ENABLE": 1})  # RTL; Copter acts at once
def test_set_mode_ack_disarmed_loiter_climb_speed_and_the_gcs_failsafe(autopilot_factory):
    ap = autopilot_factory(connect=False)
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0
    beat(conn)
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 4, 1)

    # LOITER while disarmed is taken before a position (Copter skips the checks), arming is not.
    assert set_mode(conn, 5) == mavlink.MAV_RESULT_ACCEPTED
    recv(conn, "HEARTBEAT", 5, lambda m: m.custom_mode == 5)
    ekf = recv(conn, "EKF_STATUS_REPORT", 10)
    if not ekf.flags & EKF_PRED_POS_HORIZ_ABS:
        conn.arducopter_arm()
        ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_COMPONENT_ARM_DISARM)
        assert ack.result == mavlink.MAV_RESULT_FAILED
        assert recv(conn, "STATUSTEXT", 5, lambda m: m.text.startswith("PreArm: "))
        recv(conn, "HEARTBEAT", 5, lambda m: not m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
    assert set_mode(conn, 99) == mavlink.MAV_RESULT_FAILED, "no such mode"
    wait_armable(conn)

    # GUIDED take-off, then a climb at DO_CHANGE_SPEED's 1 m/s (WPNAV_SPEED_UP is 2.5 m/s).
    assert set_mode(conn, 4) == mavlink.MAV_RESULT_ACCEPTED
    conn.arducopter_arm()
    recv_beating(conn, "STATUSTEXT", 15, lambda m: m.text == "Arming motors")
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 10)
    recv_beating(conn, "GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt >= 9500)
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_DO_CHANGE_SPEED, 0, 2, 1.0, -1, 0, 0, 0, 0)
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_DO_CHANGE_SPEED)
    assert ack.result == mavlink.MAV_RESULT_ACCEPTED
    here = recv(conn, "GLOBAL_POSITION_INT", 5)
    conn.mav.set_position_target_global_int_send(
        0, conn.target_system, 0, mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 0b0000111111111000,
        here.lat, here.lon, 20.0, 0, 0, 0, 0, 0, 0, 0, 0)
    climbs = []
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline and relative_alt_m(conn) < 17.0:
        climbs.append(recv_beating(conn, "VFR_HUD", 5, lambda m: True).climb)
    assert climbs and 0.7 < max(climbs) < 1.3, f"climb at 1 m/s: {max(climbs, default=None)}"

    # The ground station falls silent: Copter's GCS failsafe, the return shown, CRITICAL.
    set_heartbeats(conn, False)  # the package's own 1 Hz heartbeat, sent from its keeper thread
    assert recv(conn, "STATUSTEXT", 40, lambda m: m.text == "GCS Failsafe").severity == (
        mavlink.MAV_SEVERITY_WARNING)
    hb = recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 6)
    assert hb.system_status == mavlink.MAV_STATE_CRITICAL
    beat(conn)
    assert recv_beating(conn, "STATUSTEXT", 10, lambda m: m.text == "GCS Failsafe Cleared")
    recv_beating(conn, "HEARTBEAT", 10, lambda m: m.system_status == mavlink.MAV_STATE_ACTIVE)
