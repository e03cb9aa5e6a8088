#!/usr/bin/env python3
"""Upload a mission from a JSON plan and optionally fly it.

Usage:
    python gcs-scripts/mission.py PLAN.json [--fly] [--connection udpin:0.0.0.0:14550] [--timeout S]

The plan (see plans/square.json); positions are metres north/east of home, altitudes metres above
home:

    {"takeoff_alt": 3,                  required, > 0
     "speed": 5,                        optional: DO_CHANGE_SPEED [m/s] after the take-off
     "waypoints": [{"north": 5, "east": 0, "alt": 3, "hold": 0}, ...],   required, "hold" [s] optional
     "rtl": true,                       optional (default true): end with RETURN_TO_LAUNCH,
                                        false: land at the last waypoint
     "rtl_alt": 5}                      optional: sets RTL_RETURN_ALT [m] before the upload

Items go up as MISSION_ITEM_INT in MAV_FRAME_GLOBAL_RELATIVE_ALT_INT: latitude/longitude in degE7
from home (HOME_POSITION) by the equirectangular approximation with R = 6371000 m. The
MISSION_ACK must be ACCEPTED (otherwise ``error:`` names the MAV_MISSION_RESULT). With --fly the
script switches to AUTO.MISSION, arms, prints each MISSION_ITEM_REACHED and waits until the vehicle
has landed and disarmed (or the mission is COMPLETE), then prints the final position. A bad plan
exits with status 2 naming the file and field; refusals and timeouts exit with 1.
"""
import functools
import json
import math
import pathlib
import time

import common
from common import mavlink

MISSION_STATE_COMPLETE = 5


def _number(obj, key, where, required=True, default=None, minimum=None, positive=False):
    if key not in obj:
        if required:
            raise common.UsageError(f"{where}: missing field \"{key}\"")
        return default
    v = obj[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise common.UsageError(f"{where}: field \"{key}\" must be a number, not {json.dumps(v)}")
    if positive and v <= 0:
        raise common.UsageError(f"{where}: field \"{key}\" must be > 0, not {v}")
    if minimum is not None and v < minimum:
        raise common.UsageError(f"{where}: field \"{key}\" must be >= {minimum}, not {v}")
    return float(v)


def load_plan(path):
    """The validated plan as a dict; UsageError naming the file and the field otherwise."""
    try:
        plan = json.loads(pathlib.Path(path).read_text())
    except OSError as e:
        raise common.UsageError(f"{path}: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise common.UsageError(f"{path}: invalid JSON: {e}") from None
    if not isinstance(plan, dict):
        raise common.UsageError(f"{path}: the plan must be a JSON object")
    known = {"takeoff_alt", "speed", "waypoints", "rtl", "rtl_alt"}
    for key in plan:
        if key not in known:
            raise common.UsageError(f"{path}: unknown field \"{key}\" (known: {', '.join(sorted(known))})")
    out = {
        "takeoff_alt": _number(plan, "takeoff_alt", path, positive=True),
        "speed": _number(plan, "speed", path, required=False, positive=True),
        "rtl_alt": _number(plan, "rtl_alt", path, required=False, positive=True),
    }
    if out["speed"] is not None and out["speed"] > 30:
        raise common.UsageError(f"{path}: field \"speed\" must be <= 30 m/s")
    rtl = plan.get("rtl", True)
    if not isinstance(rtl, bool):
        raise common.UsageError(f"{path}: field \"rtl\" must be true or false")
    out["rtl"] = rtl
    if "waypoints" not in plan:
        raise common.UsageError(f"{path}: missing field \"waypoints\"")
    wps = plan["waypoints"]
    if not isinstance(wps, list) or not wps:
        raise common.UsageError(f"{path}: field \"waypoints\" must be a non-empty list")
    out["waypoints"] = []
    for i, wp in enumerate(wps):
        where = f"{path}: waypoints[{i}]"
        if not isinstance(wp, dict):
            raise common.UsageError(f"{where}: must be an object")
        for key in wp:
            if key not in ("north", "east", "alt", "hold"):
                raise common.UsageError(f"{where}: unknown field \"{key}\"")
        out["waypoints"].append({
            "north": _number(wp, "north", where),
            "east": _number(wp, "east", where),
            "alt": _number(wp, "alt", where, positive=True),
            "hold": _number(wp, "hold", where, required=False, default=0.0, minimum=0),
        })
    return out


def to_global(home_lat, home_lon, north, east):
    """degE7 latitude/longitude of a point `north`/`east` metres from home (equirectangular)."""
    lat = home_lat + math.degrees(north / common.EARTH_RADIUS_M)
    lon = home_lon + math.degrees(east / (common.EARTH_RADIUS_M * math.cos(math.radians(home_lat))))
    return round(lat * 1e7), round(lon * 1e7)


def mission_items(plan, home_lat, home_lon):
    """(command, x, y, z, p1, p2, p3, description) per item."""
    lat0, lon0 = to_global(home_lat, home_lon, 0.0, 0.0)
    items = [(mavlink.MAV_CMD_NAV_TAKEOFF, lat0, lon0, plan["takeoff_alt"], 0, 0, 0,
              f"take-off to {plan['takeoff_alt']:g} m")]
    if plan["speed"] is not None:
        items.append((mavlink.MAV_CMD_DO_CHANGE_SPEED, 0, 0, 0, 1, plan["speed"], -1, f"speed {plan['speed']:g} m/s"))
    for i, wp in enumerate(plan["waypoints"], 1):
        lat, lon = to_global(home_lat, home_lon, wp["north"], wp["east"])
        items.append((mavlink.MAV_CMD_NAV_WAYPOINT, lat, lon, wp["alt"], wp["hold"], 0, 0,
                      f"waypoint {i}: north {wp['north']:g} east {wp['east']:g} alt {wp['alt']:g}"))
    if plan["rtl"]:
        items.append((mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, 0, 0, 0, 0, 0, 0, "return to launch"))
    else:
        last = items[-1]
        items.append((mavlink.MAV_CMD_NAV_LAND, last[1], last[2], 0, 0, 0, 0, "land at the last waypoint"))
    return items


def upload(conn, items, timeout):
    """MISSION_COUNT, then one MISSION_ITEM_INT per request; MissionError unless ACCEPTED. While
    the autopilot is silent, the last message sent (the count, then the last item) goes again
    every `common.RESEND_S`: the autopilot re-requests a lost item itself, but not a lost count
    or a lost last item."""
    def send_count():
        conn.mav.mission_count_send(conn.target_system, conn.target_component, len(items), 0)

    def send_item(seq):
        command, x, y, z, p1, p2, p3, _ = items[seq]
        conn.mav.mission_item_int_send(conn.target_system, conn.target_component, seq,
                                       mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, command, 0, 1,
                                       p1, p2, p3, common.NAN, x, y, z, 0)

    last_sent = send_count
    send_count()
    start = time.monotonic()
    wanted = ["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"]
    while True:
        deadline = time.monotonic() + timeout
        while True:
            remaining = deadline - time.monotonic()
            try:
                m = common.wait(conn, wanted, timeout=min(max(remaining, 0.0), common.RESEND_S),
                                what="MISSION_REQUEST_INT or MISSION_ACK")
                break
            except common.LinkTimeout:
                if time.monotonic() >= deadline:
                    raise common.LinkTimeout(f"timed out after {timeout:g} s waiting for MISSION_REQUEST_INT "
                                             "or MISSION_ACK") from None
                last_sent()
        if m.get_type() == "MISSION_ACK":
            if m.type != mavlink.MAV_MISSION_ACCEPTED:
                reason = common.recent_text(conn, start)
                raise common.MissionError(f"mission refused: {common.enum_name('MAV_MISSION_RESULT', m.type)}"
                                          + (f" ({reason})" if reason else ""))
            return
        if m.seq >= len(items):
            raise common.MissionError(f"the autopilot asked for item {m.seq} of {len(items)}")
        last_sent = functools.partial(send_item, m.seq)
        last_sent()


def fly(conn, items, home, timeout, stall_s=60.0):
    """AUTO.MISSION, arm, report MISSION_ITEM_REACHED until disarmed (or COMPLETE without a landing)."""
    common.set_mode(conn, common.AUTO_MISSION)
    common.arm(conn)
    print("flying", flush=True)
    ends_on_ground = items[-1][0] in (mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, mavlink.MAV_CMD_NAV_LAND)
    current = None
    progress = time.monotonic()  # last item change or movement: a stalled mission times out
    while True:
        m = common.recv(conn, 1.0)
        now = time.monotonic()
        kind = None if m is None else m.get_type()
        if kind == "MISSION_ITEM_REACHED":
            progress = now
            desc = items[m.seq][7] if m.seq < len(items) else "?"
            print(f"reached item {m.seq} ({desc})", flush=True)
        elif kind == "MISSION_CURRENT":
            if m.seq != current:
                current, progress = m.seq, now
            if m.mission_state == MISSION_STATE_COMPLETE and not ends_on_ground:
                print("mission complete", flush=True)
                break
        elif kind == "HEARTBEAT" and m.get_srcComponent() == conn.target_component and not common.is_armed(m):
            print("landed and disarmed", flush=True)
            break
        elif kind == "GLOBAL_POSITION_INT" and math.hypot(m.vx, m.vy, m.vz) > 10:  # cm/s
            progress = now
        if now - progress > stall_s + timeout:
            raise common.LinkTimeout(f"the mission made no progress for {stall_s + timeout:g} s")
    g = common.request_message(conn, mavlink.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, "GLOBAL_POSITION_INT")
    north = math.radians(g.lat * 1e-7 - home[0]) * common.EARTH_RADIUS_M
    east = math.radians(g.lon * 1e-7 - home[1]) * common.EARTH_RADIUS_M * math.cos(math.radians(home[0]))
    print(f"final position: north {north:+.2f} m, east {east:+.2f} m, up {g.relative_alt * 1e-3:+.2f} m", flush=True)


def main(argv=None):
    p = common.parser(__doc__.split("\n\n")[0])
    p.add_argument("plan", help="JSON plan file")
    p.add_argument("--fly", action="store_true", help="fly the mission after the upload")
    args = p.parse_args(argv)
    plan = load_plan(args.plan)

    conn = common.connect(args.connection, args.timeout)
    if plan["rtl_alt"] is not None:
        common.param_set(conn, "RTL_RETURN_ALT", plan["rtl_alt"])
        print(f"RTL_RETURN_ALT = {plan['rtl_alt']:g}", flush=True)
    home = common.home_position(conn)
    print(f"home: {home[0]:.7f} {home[1]:.7f} {home[2]:.2f} m AMSL", flush=True)
    items = mission_items(plan, home[0], home[1])
    upload(conn, items, args.timeout)
    print(f"uploaded {len(items)} items:", flush=True)
    for seq, item in enumerate(items):
        print(f"  {seq}: {common.command_name(item[0])}: {item[7]}", flush=True)
    if args.fly:
        fly(conn, items, home, args.timeout)
    return 0


if __name__ == "__main__":
    common.script_main(main)
