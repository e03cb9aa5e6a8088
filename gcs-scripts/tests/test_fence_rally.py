"""Fence and rally plans over the mission protocol, driven by pymavlink on ephemeral ports: a
QGroundControl `.plan` (geoFence polygons and circles, rallyPoints) goes up as QGC's plan
managers send it (MISSION_COUNT / MISSION_REQUEST_INT / MISSION_ITEM_INT with mission_type 1 and
2), comes back identical, is cleared per type and all at once; a vehicle flown out of an
inclusion fence runs GF_ACTION with its STATUSTEXT; RTL lands at a nearer rally point."""
import os

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

from test_autopilot_link import (  # noqa: E402
    ACCEPTED, HOME_LAT, HOME_LON, METRE_LAT, METRE_LON, NAN, Autopilot, int32_bits)

FENCE, RALLY, ALL = 1, 2, 255
MAV_FRAME_GLOBAL, MAV_FRAME_GLOBAL_RELATIVE_ALT = 0, 3
RTL_MODE = (4 << 16) | (5 << 24)


def deg(north_m, east_m):
    """[lat, lon] in degrees `north_m` / `east_m` metres from home, as a `.plan` stores them."""
    return [(HOME_LAT + north_m * METRE_LAT) * 1e-7, (HOME_LON + east_m * METRE_LON) * 1e-7]


def qgc_plan(half_m=15.0):
    """A QGC `.plan` (the parts this test uses): an inclusion square of ±`half_m` about home, an
    exclusion circle of 3 m north-west, two rally points."""
    return {
        "fileType": "Plan",
        "groundStation": "QGroundControl",
        "version": 1,
        "geoFence": {
            "version": 2,
            "polygons": [{"inclusion": True, "version": 1, "polygon": [
                deg(-half_m, -half_m), deg(half_m, -half_m), deg(half_m, half_m), deg(-half_m, half_m)]}],
            "circles": [{"inclusion": False, "version": 1, "circle": {"center": deg(-8, -8), "radius": 3}}],
        },
        "rallyPoints": {"version": 2, "points": [deg(30, 0) + [10.0], deg(-60, 0) + [10.0]]},
    }


def fence_items(plan):
    """The fence items QGC's GeoFenceManager sends: every polygon's vertices (param1 the vertex
    count), then every circle (param1 the radius), all in MAV_FRAME_GLOBAL with altitude 0:
    (command, frame, param1, x, y, z)."""
    items = []
    for poly in plan["geoFence"]["polygons"]:
        cmd = 5001 if poly["inclusion"] else 5002
        items += [(cmd, MAV_FRAME_GLOBAL, float(len(poly["polygon"])), round(lat * 1e7), round(lon * 1e7), 0.0)
                  for lat, lon in poly["polygon"]]
    for c in plan["geoFence"]["circles"]:
        lat, lon = c["circle"]["center"]
        cmd = 5003 if c["inclusion"] else 5004
        items.append((cmd, MAV_FRAME_GLOBAL, float(c["circle"]["radius"]), round(lat * 1e7), round(lon * 1e7), 0.0))
    return items


def rally_items(plan):
    """QGC's RallyPointManager items: NAV_RALLY_POINT in MAV_FRAME_GLOBAL_RELATIVE_ALT."""
    return [(5100, MAV_FRAME_GLOBAL_RELATIVE_ALT, 0.0, round(lat * 1e7), round(lon * 1e7), alt)
            for lat, lon, alt in plan["rallyPoints"]["points"]]


def upload(ap, mission_type, items):
    """MISSION_COUNT, then each MISSION_ITEM_INT the vehicle asks for; the final MISSION_ACK (the
    STATUSTEXTs meanwhile are kept for `ap.wait`)."""
    ap.gcs.mav.mission_count_send(1, 1, len(items), mission_type)
    texts = []
    while True:
        m = ap.wait(lambda m: m.get_type() != "MISSION_ACK" or m.mission_type == mission_type,
                    ["MISSION_REQUEST_INT", "MISSION_ACK", "STATUSTEXT"], 3)
        assert m is not None, "the upload stalled"
        if m.get_type() == "STATUSTEXT":
            texts.append(m)
            continue
        if m.get_type() == "MISSION_ACK":
            ap.pending += texts
            return m
        assert m.mission_type == mission_type
        cmd, frame, p1, x, y, z = items[m.seq]
        ap.gcs.mav.mission_item_int_send(1, 1, m.seq, frame, cmd, 0, 0, p1, 0, 0, 0, x, y, z, mission_type)


def download(ap, mission_type):
    """The plan's items as (command, frame, param1, x, y, z), as QGC downloads them."""
    ap.gcs.mav.mission_request_list_send(1, 1, mission_type)
    count = ap.wait(lambda m: m.mission_type == mission_type, "MISSION_COUNT", 3)
    assert count is not None
    items = []
    for seq in range(count.count):
        ap.gcs.mav.mission_request_int_send(1, 1, seq, mission_type)
        it = ap.wait(lambda m: m.seq == seq and m.mission_type == mission_type, "MISSION_ITEM_INT", 3)
        assert it is not None, seq
        items.append((it.command, it.frame, it.param1, it.x, it.y, it.z))
    ap.gcs.mav.mission_ack_send(1, 1, 0, mission_type)
    return items


def clear(ap, mission_type):
    ap.gcs.mav.mission_clear_all_send(1, 1, mission_type)
    ack = ap.wait(lambda m: m.mission_type == mission_type, "MISSION_ACK", 3)
    assert ack is not None and ack.type == 0, ack


def test_a_qgc_plan_fence_and_rally_upload_download_and_clear():
    ap = Autopilot()
    try:
        ap.heartbeat()
        assert ap.command(512, 148).result == ACCEPTED
        caps = ap.wait(lambda m: True, "AUTOPILOT_VERSION", 2).capabilities
        fence_cap = mavutil.mavlink.MAV_PROTOCOL_CAPABILITY_MISSION_FENCE
        rally_cap = mavutil.mavlink.MAV_PROTOCOL_CAPABILITY_MISSION_RALLY
        assert caps & fence_cap and caps & rally_cap, caps
        plan = qgc_plan()
        fence, rally = fence_items(plan), rally_items(plan)
        assert upload(ap, FENCE, fence).type == 0
        assert upload(ap, RALLY, rally).type == 0
        assert download(ap, FENCE) == fence
        assert download(ap, RALLY) == rally
        assert download(ap, 0) == [], "the mission is another plan"
        # A refused fence (a two-vertex polygon) leaves the stored one.
        bad = [(5001, MAV_FRAME_GLOBAL, 2.0, HOME_LAT, HOME_LON, 0.0)] * 2
        assert upload(ap, FENCE, bad).type == mavutil.mavlink.MAV_MISSION_ERROR
        text = ap.wait(lambda m: "Fence item" in m.text, "STATUSTEXT", 2)
        assert text is not None and "refused" in text.text
        assert download(ap, FENCE) == fence
        clear(ap, FENCE)
        assert download(ap, FENCE) == [] and download(ap, RALLY) == rally
        clear(ap, ALL)
        assert download(ap, RALLY) == []
    finally:
        ap.close()


def test_flying_out_of_an_inclusion_fence_runs_gf_action():
    ap = Autopilot()
    try:
        ap.heartbeat()
        ap.gcs.mav.param_set_send(1, 1, b"GF_ACTION", int32_bits(3), 6)
        assert ap.wait(lambda m: m.param_id == "GF_ACTION", "PARAM_VALUE", 2) is not None
        assert upload(ap, FENCE, fence_items(qgc_plan(half_m=15.0))).type == 0
        ap.take_off()
        # DO_REPOSITION 40 m north, out through the fence.
        ap.gcs.mav.command_int_send(1, 1, 6, 192, 0, 0, -1, 1, 0, NAN, HOME_LAT + round(40 * METRE_LAT), HOME_LON, 3.0)
        breach = ap.wait(lambda m: m.text.startswith("Geofence breached"), "STATUSTEXT", 20)
        assert breach is not None and breach.text == "Geofence breached (outside inclusion zone 1)"
        assert breach.severity == mavutil.mavlink.MAV_SEVERITY_CRITICAL
        assert ap.wait(lambda m: m.custom_mode == RTL_MODE, "HEARTBEAT", 3) is not None, "GF_ACTION 3: return"
        pos = ap.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
        assert 14.0 < pos.x < 20.0, f"turned back at the fence: {pos.x:.1f} m"
        assert ap.wait(lambda m: m.text.startswith("Geofence breached"), "STATUSTEXT", 3) is None, "once"
    finally:
        ap.close()


def test_rtl_lands_at_a_nearer_rally_point():
    ap = Autopilot()
    try:
        ap.heartbeat()
        ap.gcs.mav.param_set_send(1, 1, b"RTL_RETURN_ALT", 5.0, 9)
        assert ap.wait(lambda m: m.param_id == "RTL_RETURN_ALT", "PARAM_VALUE", 2) is not None
        assert upload(ap, RALLY, rally_items(qgc_plan())).type == 0
        ap.take_off()
        ap.gcs.mav.command_int_send(1, 1, 6, 192, 0, 0, -1, 1, 0, NAN, HOME_LAT + round(20 * METRE_LAT), HOME_LON, 3.0)
        assert ap.wait(lambda m: abs(m.x - 20) < 0.3, "LOCAL_POSITION_NED", 15) is not None
        assert ap.command(20).result == ACCEPTED
        landed = ap.wait(lambda m: not m.base_mode & 128, "HEARTBEAT", 60)
        assert landed is not None, "returned, landed and disarmed"
        pos = ap.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
        assert abs(pos.x - 30) < 0.5 and abs(pos.y) < 0.5, f"at the rally point 30 m north: {pos.x:.1f}, {pos.y:.1f}"
    finally:
        ap.close()
