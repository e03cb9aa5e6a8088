#!/usr/bin/env python3
"""Arm, take off, hover, land and wait for the auto-disarm.

Usage:
    python gcs-scripts/takeoff_land.py [--height M] [--hold S] [--connection udpin:0.0.0.0:14550] [--timeout S]

Sends NAV_TAKEOFF (p7 = home AMSL + --height; without --height the autopilot's MIS_TAKEOFF_ALT),
arms, waits for the take-off to complete (EXTENDED_SYS_STATE IN_AIR), hovers --hold seconds
printing LOCAL_POSITION_NED (north, east, up relative to home), sends NAV_LAND and waits for the
touch-down and the autopilot's auto-disarm (COM_DISARM_LAND). Exit status 0 on success, 1 when a
command is refused or a wait times out (``error: ...`` on stderr), 2 for bad usage.
"""
import common


def main(argv=None):
    p = common.parser(__doc__.split("\n\n")[0])
    p.add_argument("--height", type=float, default=None, help="take-off height above home [m] (default MIS_TAKEOFF_ALT)")
    p.add_argument("--hold", type=float, default=5.0, help="hover time before landing [s] (default 5)")
    args = p.parse_args(argv)
    if args.height is not None and not 0 < args.height <= 1000:
        p.error("--height must be in (0, 1000] m")
    if args.hold < 0:
        p.error("--hold must be >= 0")

    conn = common.connect(args.connection, args.timeout)
    start = common.local_position(conn)
    print(f"start position: {common.format_position(start)}", flush=True)
    height = common.takeoff(conn, args.height)
    pos = common.local_position(conn)
    print(f"took off to {height:g} m: {common.format_position(pos)}", flush=True)

    def show(m):
        if m.get_type() == "LOCAL_POSITION_NED":
            print(f"hover: {common.format_position(m)}", flush=True)

    common.sleep(conn, args.hold, show)
    print("landing", flush=True)
    common.land(conn)
    descent = 15.0 + 3.0 * height
    common.wait_landed_state(conn, common.ON_GROUND, descent)
    common.wait_disarmed(conn, 10.0 + args.timeout)
    pos = common.local_position(conn)
    print(f"landed and disarmed: {common.format_position(pos)}", flush=True)
    return 0


if __name__ == "__main__":
    common.script_main(main)
