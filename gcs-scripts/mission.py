#!/usr/bin/env python3
"""Upload a mission from a plan file and optionally fly it.

Usage:
    python gcs-scripts/mission.py PLAN [--fly] [--wpl-skip-home] [--connection udpin:0.0.0.0:14550]
                                  [--timeout S]

PLAN is rotorpilot's JSON plan, a QGroundControl ``.plan`` or a QGC WPL 110 text file. The JSON
plan (see plans/square.json); positions are metres north/east of home, altitudes metres above
home:

    {"takeoff_alt": 3,                  required, > 0
     "speed": 5,                        optional: DO_CHANGE_SPEED [m/s] after the take-off
     "waypoints": [{"north": 5, "east": 0, "alt": 3, "hold": 0}, ...],   required, "hold" [s] optional
     "rtl": true,                       optional (default true): end with RETURN_TO_LAUNCH,
                                        false: land at the last waypoint
     "rtl_alt": 5}                      optional: sets RTL_RETURN_ALT [m] before the upload
                                        (ArduCopter: RTL_ALT, in cm)

Its items go up as MISSION_ITEM_INT in MAV_FRAME_GLOBAL_RELATIVE_ALT_INT: latitude/longitude in
degE7 from home (HOME_POSITION) by the equirectangular approximation with R = 6371000 m. A QGC
``.plan``'s mission items go up as they are (frame, params), then its geofence and rally points
(mission types 1 and 2) if it has any; a WPL file's items go up as they are (--wpl-skip-home
drops its first line, the home position ArduPilot and MAVProxy write first). The MISSION_ACK
must be ACCEPTED (otherwise ``error:`` names the MAV_MISSION_RESULT). To an ArduCopter vehicle
the items go up after its home slot, item 0, and are numbered here as in the file. With --fly the
script starts the mission (PX4: AUTO.MISSION, arm; ArduCopter: GUIDED, arm, AUTO), prints each
MISSION_ITEM_REACHED and waits until the vehicle has landed and disarmed (or the mission is
COMPLETE), then prints the final position. A bad plan
exits with status 2 naming the file and field; refusals and timeouts exit with 1.
"""
import json
import math
import pathlib
import time

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink
from rotorpilot_gcs.plans import GLOBAL_FRAMES

MISSION_STATE_COMPLETE = 5


def describe(item):
    """What an item is, for the upload listing."""
    if item.description:
        return item.description
    if item.frame in GLOBAL_FRAMES and (item.x or item.y):
        return f"lat {item.x * 1e-7:.7f} lon {item.y * 1e-7:.7f} alt {item.z:g} m"
    return f"params {item.param1:g} {item.param2:g} {item.param3:g} {item.param4:g}"


def load(path, skip_home):
    """(kind, plan) of the file: ("json", load_plan's dict), ("qgc", QgcPlan) or ("wpl", items)."""
    try:
        head = pathlib.Path(path).read_text()[:4096]
    except OSError as e:
        raise gcs.UsageError(f"{path}: {e.strerror}") from None
    if head.lstrip().startswith("QGC WPL"):
        return "wpl", gcs.plans.load_wpl(path, skip_home=skip_home)
    try:
        is_qgc = json.loads(pathlib.Path(path).read_text()).get("fileType") == "Plan"
    except (json.JSONDecodeError, AttributeError):
        is_qgc = False
    if is_qgc:
        return "qgc", gcs.plans.load_qgc_plan(path)
    return "json", gcs.plans.load_plan(path)


def fly(conn, items, home, timeout, stall_s=60.0):
    """Starts the mission, reports MISSION_ITEM_REACHED until disarmed (or COMPLETE without a
    landing)."""
    gcs.flight.start_mission(conn)
    home_slot = gcs.missions.home_slot(conn)  # ArduCopter's seqs count its home
    print("flying", flush=True)
    ends_on_ground = items[-1].command in (mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, mavlink.MAV_CMD_NAV_LAND)
    current = None
    progress = time.monotonic()  # last item change or movement: a stalled mission times out
    while True:
        m = gcs.link.recv(conn, 1.0)
        now = time.monotonic()
        kind = None if m is None else m.get_type()
        if kind == "MISSION_ITEM_REACHED":
            progress = now
            index = m.seq - home_slot
            desc = describe(items[index]) if 0 <= index < len(items) else "?"
            print(f"reached item {index} ({desc})", flush=True)
        elif kind == "MISSION_CURRENT":
            if m.seq != current:
                current, progress = m.seq, now
            if m.mission_state == MISSION_STATE_COMPLETE and not ends_on_ground:
                print("mission complete", flush=True)
                break
        elif kind == "HEARTBEAT" and m.get_srcComponent() == conn.target_component and not gcs.telemetry.is_armed(m):
            print("landed and disarmed", flush=True)
            break
        elif kind == "GLOBAL_POSITION_INT" and math.hypot(m.vx, m.vy, m.vz) > 10:  # cm/s
            progress = now
        if now - progress > stall_s + timeout:
            raise gcs.LinkTimeout(f"the mission made no progress for {stall_s + timeout:g} s")
    g = gcs.commands.request_message(conn, mavlink.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, "GLOBAL_POSITION_INT")
    north, east = gcs.geo.global_to_offset(home[0], home[1], g.lat * 1e-7, g.lon * 1e-7)
    print(f"final position: north {north:+.2f} m, east {east:+.2f} m, up {g.relative_alt * 1e-3:+.2f} m", flush=True)


def main(argv=None):
    p = gcs.cli.parser(__doc__.split("\n\n")[0])
    p.add_argument("plan", help="plan file: rotorpilot JSON plan, QGC .plan or QGC WPL 110")
    p.add_argument("--fly", action="store_true", help="fly the mission after the upload")
    p.add_argument("--wpl-skip-home", action="store_true", help="drop a WPL file's first line (its home position)")
    args = p.parse_args(argv)
    kind, plan = load(args.plan, args.wpl_skip_home)

    conn = gcs.connect(args.connection, args.timeout)
    if kind == "json" and plan["rtl_alt"] is not None:
        if gcs.link.personality(conn) == gcs.modes.ARDUPILOT:
            gcs.params.param_set(conn, "RTL_ALT", round(plan["rtl_alt"] * 100))
            print(f"RTL_ALT = {round(plan['rtl_alt'] * 100)} cm", flush=True)
        else:
            gcs.params.param_set(conn, "RTL_RETURN_ALT", plan["rtl_alt"])
            print(f"RTL_RETURN_ALT = {plan['rtl_alt']:g}", flush=True)
    home = gcs.telemetry.home_position(conn)
    print(f"home: {home[0]:.7f} {home[1]:.7f} {home[2]:.2f} m AMSL", flush=True)
    items = {"json": lambda: gcs.plans.plan_items(plan, home[0], home[1]), "qgc": lambda: plan.mission,
             "wpl": lambda: plan}[kind]()
    if not items:
        raise gcs.UsageError(f"{args.plan}: no mission items")
    gcs.missions.upload_mission(conn, items, timeout=args.timeout)
    print(f"uploaded {len(items)} items:", flush=True)
    for seq, item in enumerate(items):
        print(f"  {seq}: {gcs.names.command_name(item.command)}: {describe(item)}", flush=True)
    if kind == "qgc":
        extras = (("fence", gcs.missions.FENCE, plan.fence), ("rally", gcs.missions.RALLY, plan.rally))
        for name, mission_type, extra in extras:
            if extra:
                gcs.missions.upload_mission(conn, extra, mission_type, timeout=args.timeout)
                print(f"uploaded {len(extra)} {name} items", flush=True)
    if args.fly:
        fly(conn, items, home, args.timeout)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
