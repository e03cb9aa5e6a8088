#!/usr/bin/env python3
"""Fly a square with position setpoints (PX4's OFFBOARD, ArduCopter's GUIDED) and report how well
the corners were reached.

Usage:
    python gcs-scripts/offboard_square.py [--side M] [--leg-time S] [--height M] [--land]
                                          [--connection udpin:0.0.0.0:14550] [--timeout S]

Takes off (to --height above home, default MIS_TAKEOFF_ALT), starts streaming
SET_POSITION_TARGET_LOCAL_NED (LOCAL_NED, type_mask 2552: position + yaw) at 20 Hz at the current
position, switches to the mode that takes them (OFFBOARD; GUIDED on an ArduCopter vehicle,
which the take-off already left it in), then moves the setpoint to the corners north, north-east, east of
the start and back to the start at the take-off altitude, --leg-time seconds each. At the end of
each leg a fresh LOCAL_POSITION_NED is requested and its distance to the corner printed; the
largest is reported as ``max corner error: E m``. Then the vehicle is switched to hold (AUTO.LOITER;
ArduCopter: LOITER), or
with --land lands and auto-disarms. Exit status 0 on success, 1 on a refusal or timeout, 2 for
bad usage.
"""
import math
import time

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink

# REQUEST_MESSAGE sends at a corner, each answered within 0.3 s or sent again.
CORNER_REQUESTS = 3


def main(argv=None):
    p = gcs.cli.parser(__doc__.split("\n\n")[0])
    p.add_argument("--side", type=float, default=2.0, help="side of the square [m] (default 2)")
    p.add_argument("--leg-time", type=float, default=4.0, help="seconds per corner (default 4)")
    p.add_argument("--height", type=float, default=None,
                   help="take-off height above home [m] (default MIS_TAKEOFF_ALT)")
    p.add_argument("--land", action="store_true",
                   help="land at the end instead of holding (AUTO.LOITER, Copter's LOITER)")
    args = p.parse_args(argv)
    if not 0 < args.side <= 100:
        p.error("--side must be in (0, 100] m")
    if not 1 <= args.leg_time <= 120:
        p.error("--leg-time must be in [1, 120] s")
    if args.height is not None and not 0 < args.height <= 1000:
        p.error("--height must be in (0, 1000] m")

    conn = gcs.connect(args.connection, args.timeout)
    height = gcs.flight.takeoff(conn, args.height)
    start = gcs.telemetry.local_position(conn)
    yaw = gcs.commands.request_message(conn, mavlink.MAVLINK_MSG_ID_ATTITUDE, "ATTITUDE").yaw
    print(f"took off to {height:g} m: {gcs.telemetry.format_position(start)}", flush=True)

    x0, y0, z0 = start.x, start.y, start.z
    gcs.offboard.set_setpoint(conn, x0, y0, z0, yaw)
    gcs.link.sleep(conn, 0.3)  # proof of life before the mode switch
    setpoints = gcs.flight.mode_for(conn, gcs.modes.SETPOINTS)
    gcs.flight.set_mode(conn, setpoints)
    print(setpoints, flush=True)

    corners = [(x0 + args.side, y0), (x0 + args.side, y0 + args.side), (x0, y0 + args.side), (x0, y0)]
    worst = 0.0
    for i, (x, y) in enumerate(corners, 1):
        gcs.offboard.set_setpoint(conn, x, y, z0, yaw)
        gcs.link.sleep(conn, args.leg_time - 0.3)
        sent = time.monotonic()
        fresh = []
        for _ in range(CORNER_REQUESTS):  # the same request again if the answer was lost
            conn.mav.command_long_send(conn.target_system, conn.target_component, mavlink.MAV_CMD_REQUEST_MESSAGE,
                                       0, mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED, *([gcs.commands.NAN] * 6))
            gcs.link.sleep(conn, 0.3, lambda m: fresh.append(m) if m.get_type() == "LOCAL_POSITION_NED" else None)
            if fresh:
                break
        if not fresh:
            latest = gcs.link.latest(conn, "LOCAL_POSITION_NED", since=sent - 1.5)
            if latest is None:
                raise gcs.LinkTimeout(f"no LOCAL_POSITION_NED at corner {i}")
            fresh = [latest]
        pos = fresh[-1]
        err = math.sqrt((pos.x - x) ** 2 + (pos.y - y) ** 2 + (pos.z - z0) ** 2)
        worst = max(worst, err)
        print(f"corner {i}: target north {x:+.2f} east {y:+.2f} up {-z0:+.2f}; "
              f"at {gcs.telemetry.format_position(pos)}; error {err:.3f} m", flush=True)

    print(f"max corner error: {worst:.3f} m", flush=True)
    if args.land:
        gcs.flight.land(conn)
        gcs.offboard.stop_setpoints(conn)
        print("landing", flush=True)
        gcs.telemetry.wait_landed_state(conn, gcs.telemetry.ON_GROUND, 15.0 + 3.0 * height)
        gcs.telemetry.wait_disarmed(conn, 10.0 + args.timeout)
        print(f"landed and disarmed: {gcs.telemetry.format_position(gcs.telemetry.local_position(conn))}", flush=True)
    else:
        hold = gcs.flight.mode_for(conn, gcs.modes.HOLD)
        gcs.flight.set_mode(conn, hold)
        gcs.offboard.stop_setpoints(conn)
        print(hold, flush=True)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
