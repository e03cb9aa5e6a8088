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
import rotorpilot_gcs as gcs


def main(argv=None):
    p = gcs.cli.parser(__doc__.split("\n\n")[0])
    p.add_argument("--height", type=float, default=None,
                   help="take-off height above home [m] (default MIS_TAKEOFF_ALT)")
    p.add_argument("--hold", type=float, default=5.0, help="hover time before landing [s] (default 5)")
    args = p.parse_args(argv)
    if args.height is not None and not 0 < args.height <= 1000:
        p.error("--height must be in (0, 1000] m")
    if args.hold < 0:
        p.error("--hold must be >= 0")

    conn = gcs.connect(args.connection, args.timeout)
    start = gcs.telemetry.local_position(conn)
    print(f"start position: {gcs.telemetry.format_position(start)}", flush=True)
    height = gcs.flight.takeoff(conn, args.height)
    pos = gcs.telemetry.local_position(conn)
    print(f"took off to {height:g} m: {gcs.telemetry.format_position(pos)}", flush=True)

    def show(m):
        if m.get_type() == "LOCAL_POSITION_NED":
            print(f"hover: {gcs.telemetry.format_position(m)}", flush=True)

    gcs.link.sleep(conn, args.hold, show)
    print("landing", flush=True)
    gcs.flight.land(conn)
    descent = 15.0 + 3.0 * height
    gcs.telemetry.wait_landed_state(conn, gcs.telemetry.ON_GROUND, descent)
    gcs.telemetry.wait_disarmed(conn, 10.0 + args.timeout)
    pos = gcs.telemetry.local_position(conn)
    print(f"landed and disarmed: {gcs.telemetry.format_position(pos)}", flush=True)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
