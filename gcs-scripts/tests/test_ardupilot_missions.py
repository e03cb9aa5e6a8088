"""Missions, fences and rally points as a pymavlink script written for ArduCopter uploads and
flies them, against `rotorpilot run --autopilot ardupilot` on its default configuration
(realistic sensors; docs/ardupilot.md §6): a take-off with latitude and longitude 0 climbing in
place, a DO_JUMP taken its repeat count of times, a land with latitude and longitude 0 where the
vehicle is, a fence polygon round trip and a malformed polygon refused, and RTL to the nearest
rally point. Judged from telemetry (MISSION_CURRENT, GLOBAL_POSITION_INT, HEARTBEAT)."""
import math
import time

import pytest
from test_ardupilot_pymavlink import connect as ardupilot_connection
from test_ardupilot_pymavlink import guided_takeoff, north_of_home, recv, wait_armable

from rotorpilot_gcs import mavlink

FAST = pytest.mark.rotorpilot(autopilot="ardupilot", speedup=6)
REL = mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
DEG_E7_PER_M = 1e7 / 111_320.0


def connect(ap):
    """The pymavlink connection to `ap`, its streams asked for at 10 Hz, ready to arm."""
    conn = ardupilot_connection(ap)
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 10, 1)
    wait_armable(conn)
    return conn


def upload(conn, mission_type, items):
    """Uploads `items` ((command, frame, x, y, z, p1, p2) each) as MAVProxy does, answering
    every MISSION_REQUEST with MISSION_ITEM_INT; returns the MISSION_ACK's result and the texts
    said before it."""
    conn.mav.mission_count_send(conn.target_system, 0, len(items), mission_type)
    texts = []
    while True:
        m = recv(conn, ["MISSION_REQUEST", "MISSION_REQUEST_INT", "MISSION_ACK", "STATUSTEXT"], 10)
        if m.get_type() == "STATUSTEXT":
            texts.append(m.text)
            continue
        if m.get_type() == "MISSION_ACK":
            return m.type, texts
        assert m.get_type() == "MISSION_REQUEST", "ArduCopter asks with MISSION_REQUEST"
        command, frame, x, y, z, p1, p2 = items[m.seq]
        conn.mav.mission_item_int_send(conn.target_system, 0, m.seq, frame, command, 0, 1,
                                       p1, p2, 0, 0, x, y, z, mission_type)


def offset(home, north_m, east_m):
    """(lat, lon) [degE7] `north_m`, `east_m` from `home` (lat, lon)."""
    lat, lon = home
    return lat + round(north_m * DEG_E7_PER_M), lon + round(east_m * DEG_E7_PER_M / math.cos(math.radians(lat / 1e7)))


def metres_from(home, m):
    """(north, east) [m] of GLOBAL_POSITION_INT `m` from `home`."""
    lat, lon = home
    return (m.lat - lat) / DEG_E7_PER_M, (m.lon - lon) / DEG_E7_PER_M * math.cos(math.radians(lat / 1e7))


@FAST
def test_a_do_jump_repeats_and_take_off_and_land_at_lat_lon_0_are_here(autopilot_factory):
    conn = connect(autopilot_factory(connect=False))
    home = north_of_home(conn, 0.0)
    a, b = offset(home, 12.0, 0.0), offset(home, 12.0, 10.0)
    wp = mavlink.MAV_CMD_NAV_WAYPOINT
    items = [
        (wp, mavlink.MAV_FRAME_GLOBAL, home[0], home[1], 0, 0, 0),  # home's slot
        (mavlink.MAV_CMD_NAV_TAKEOFF, REL, 0, 0, 6, 0, 0),
        (wp, REL, a[0], a[1], 6, 0, 0),
        (wp, REL, b[0], b[1], 6, 0, 0),
        (mavlink.MAV_CMD_DO_JUMP, mavlink.MAV_FRAME_MISSION, 0, 0, 0, 2, 2),  # to seq 2, twice
        (mavlink.MAV_CMD_NAV_LAND, REL, 0, 0, 0, 0, 0),
    ]
    accepted = upload(conn, mavlink.MAV_MISSION_TYPE_MISSION, items)
    assert accepted == (mavlink.MAV_MISSION_ACCEPTED, ["Flight plan received"])
    conn.set_mode("GUIDED")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 4)
    conn.arducopter_arm()
    conn.motors_armed_wait()
    conn.set_mode("AUTO")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 3)
    # The take-off climbs where the vehicle stands.
    top = recv(conn, "GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt >= 5500)
    assert math.hypot(*metres_from(home, top)) < 1.5, metres_from(home, top)
    seqs, landed_at = [], None
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        m = recv(conn, ["MISSION_CURRENT", "GLOBAL_POSITION_INT", "HEARTBEAT"], 10)
        if m.get_type() == "MISSION_CURRENT" and (not seqs or seqs[-1] != m.seq):
            seqs.append(m.seq)
        elif m.get_type() == "GLOBAL_POSITION_INT":
            landed_at = m
        elif m.get_type() == "HEARTBEAT" and not m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED:
            break
    else:
        raise AssertionError(f"never landed: {seqs}")
    assert seqs == [1, 2, 3, 2, 3, 2, 3, 5], "jumped back twice, then on to the land"
    north, east = metres_from(home, landed_at)
    assert abs(north - 12.0) < 2.0 and abs(east - 10.0) < 2.0, "landed where the last waypoint left it"
    assert abs(landed_at.relative_alt) < 500
    assert recv(conn, "HEARTBEAT", 5).custom_mode == 3, "AUTO, as Copter keeps it after the land"


@FAST
def test_fence_round_trip_a_malformed_polygon_and_rtl_to_the_nearest_rally_point(autopilot_factory):
    conn = connect(autopilot_factory(connect=False))
    home = north_of_home(conn, 0.0)
    vertex = mavlink.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION
    corners = [offset(home, n, e) for n, e in ((-150, -150), (150, -150), (150, 150), (-150, 150))]
    fence = [(vertex, REL, lat, lon, 0, 4, 0) for lat, lon in corners]
    fence.append((mavlink.MAV_CMD_NAV_FENCE_RETURN_POINT, REL, home[0], home[1], 0, 0, 0))
    assert upload(conn, mavlink.MAV_MISSION_TYPE_FENCE, fence) == (mavlink.MAV_MISSION_ACCEPTED, [])
    conn.mav.mission_request_list_send(conn.target_system, 0, mavlink.MAV_MISSION_TYPE_FENCE)
    assert recv(conn, "MISSION_COUNT", 10).count == 5
    conn.mav.mission_request_int_send(conn.target_system, 0, 2, mavlink.MAV_MISSION_TYPE_FENCE)
    back = recv(conn, "MISSION_ITEM_INT", 10)
    assert (back.command, back.param1, back.x, back.y) == (vertex, 4, *corners[2])
    assert (back.frame, back.z) == (mavlink.MAV_FRAME_GLOBAL, 0), "ArduCopter stores no height"
    refused = upload(conn, mavlink.MAV_MISSION_TYPE_FENCE, fence[:3])
    assert refused == (mavlink.MAV_MISSION_ERROR, ["Incorrect item count", "Fence validation failed"])
    # A rally point 30 m north: from 20 m north it is nearer than home, and the return lands there.
    rally = offset(home, 30.0, 0.0)
    point = (mavlink.MAV_CMD_NAV_RALLY_POINT, REL, rally[0], rally[1], 8, 0, 0)
    accepted = upload(conn, mavlink.MAV_MISSION_TYPE_RALLY, [point])
    assert accepted == (mavlink.MAV_MISSION_ACCEPTED, ["Rally points received"])
    guided_takeoff(conn, 8)
    there = offset(home, 20.0, 0.0)
    conn.mav.mission_item_int_send(conn.target_system, 0, 0, REL, mavlink.MAV_CMD_NAV_WAYPOINT, 2, 0,
                                   0, 0, 0, 0, there[0], there[1], 8)
    recv(conn, "GLOBAL_POSITION_INT", 60, lambda m: abs(metres_from(home, m)[0] - 20.0) < 1.0)
    conn.set_mode("RTL")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 6)
    recv(conn, "HEARTBEAT", 120, lambda m: not m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
    north, east = metres_from(home, recv(conn, "GLOBAL_POSITION_INT", 5))
    assert abs(north - 30.0) < 2.0 and abs(east) < 2.0, f"landed at the rally point: {north:.1f} N {east:.1f} E"
