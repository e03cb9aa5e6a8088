#!/usr/bin/env python3
"""Arm a swarm, take it off, fly a ring formation around a moving centre with position setpoints,
and land it.

Usage:
    python gcs-scripts/swarm.py --count N [--connection URL ...] [--height M] [--radius M]
                                [--side M] [--leg-time S] [--timeout S]

One pymavlink connection per vehicle (pymavlink answers a `udpin` peer on the address it heard
last, so vehicles cannot share one socket for commands). Without --connection, vehicle i is reached
on its API link as PX4's multi-vehicle scheme and `rotorpilot run --count N` set it up:
``udpin:0.0.0.0:(14540 + i)``; or give one --connection per vehicle, e.g.
``udpout:127.0.0.1:(14580 + i)`` to talk to the vehicles' bind ports.

Each vehicle's HOME_POSITION places it in a common frame (north/east metres from the first
vehicle's home). All take off to --height, then stream SET_POSITION_TARGET_LOCAL_NED at 20 Hz
(in each vehicle's own local frame) and switch to the mode that takes them (OFFBOARD; GUIDED on an
ArduCopter vehicle: a swarm may mix both personalities): first to its slot on a ring of
--radius around the swarm's centre, then the centre flies a square of --side metres, --leg-time
seconds per leg. After each leg every vehicle's distance to its slot is printed and the largest
is reported as ``max formation error: E m``; a vehicle that left that mode is an error. Then all
land and auto-disarm. The simulation has no collisions; choose --radius and the start --spacing so
paths do not cross if that matters to you.
Exit status 0 on success, 1 on a refusal or timeout (``error: ...``), 2 for bad usage.
"""
import argparse
import math
import time

import rotorpilot_gcs as gcs

API_PORT = 14540


def ring_slots(count, radius):
    """(north, east) offsets [m] of `count` slots evenly spaced on a ring of `radius`."""
    if count == 1:
        return [(0.0, 0.0)]
    return [(radius * math.cos(2 * math.pi * k / count), radius * math.sin(2 * math.pi * k / count))
            for k in range(count)]


def home_offset(home, origin):
    """(north, east) [m] of geodetic `home` from `origin`, both (lat_deg, lon_deg, alt_m)."""
    return gcs.geo.global_to_offset(origin[0], origin[1], home[0], home[1])


def service_all(conns, seconds):
    """Keeps every link serviced (heartbeats, setpoint streams) for `seconds`."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        for conn in conns:
            gcs.link.recv(conn, 0.002)


class Member:
    """One vehicle of the swarm: its connection and where its local frame sits."""

    def __init__(self, conn, offset):
        self.conn = conn
        self.north0, self.east0 = offset
        self.target = None
        #: HEARTBEAT.custom_mode of the mode it takes the setpoints in, once switched to it.
        self.setpoint_mode = None

    def fly_to(self, north, east, up):
        """Streams the common-frame point (north, east, up) [m] as this vehicle's local setpoint."""
        self.target = (north, east, up)
        gcs.offboard.set_setpoint(self.conn, north - self.north0, east - self.east0, -up)

    def error(self):
        """Distance [m] between the vehicle and its target, from a fresh LOCAL_POSITION_NED."""
        p = gcs.telemetry.local_position(self.conn)
        north, east, up = self.target
        return math.sqrt((p.x + self.north0 - north) ** 2 + (p.y + self.east0 - east) ** 2 + (-p.z - up) ** 2)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--count", type=int, required=True, help="number of vehicles")
    p.add_argument("--connection", action="append", dest="connections", default=None,
                   help=f"one per vehicle (default udpin:0.0.0.0:({API_PORT} + i))")
    p.add_argument("--height", type=float, default=3.0, help="formation height above home [m] (default 3)")
    p.add_argument("--radius", type=float, default=2.0, help="ring radius [m] (default 2)")
    p.add_argument("--side", type=float, default=4.0, help="side of the square the centre flies [m] (default 4)")
    p.add_argument("--leg-time", type=float, default=5.0, help="seconds per leg (default 5)")
    p.add_argument("--timeout", type=float, default=gcs.DEFAULT_TIMEOUT,
                   help=f"seconds to wait for each heartbeat and reply (default {gcs.DEFAULT_TIMEOUT:g})")
    args = p.parse_args(argv)
    if not 1 <= args.count <= 255:
        p.error("--count must be in [1, 255]")
    connections = args.connections or [f"udpin:0.0.0.0:{API_PORT + i}" for i in range(args.count)]
    if len(connections) != args.count:
        p.error(f"--count {args.count} needs {args.count} --connection options, not {len(connections)}")
    if not 0.5 <= args.height <= 100 or not 0 <= args.radius <= 100 or not 0 <= args.side <= 100:
        p.error("--height must be in [0.5, 100] m, --radius and --side in [0, 100] m")
    if not 1 <= args.leg_time <= 120:
        p.error("--leg-time must be in [1, 120] s")

    conns = [gcs.connect(url, args.timeout) for url in connections]
    sysids = [c.target_system for c in conns]
    if len(set(sysids)) != len(sysids):
        raise gcs.GcsError(f"two connections reach the same vehicle: system ids {sysids}")
    homes = [gcs.telemetry.home_position(c) for c in conns]
    members = [Member(c, home_offset(h, homes[0])) for c, h in zip(conns, homes)]

    for m in members:
        gcs.flight.start_takeoff(m.conn, args.height)
    for m in members:
        gcs.flight.wait_takeoff(m.conn, args.height)
    print(f"{len(members)} vehicles in the air (systems {', '.join(map(str, sysids))})", flush=True)

    slots = ring_slots(len(members), args.radius)
    centre_n = sum(m.north0 for m in members) / len(members)
    centre_e = sum(m.east0 for m in members) / len(members)
    for m in members:
        p = gcs.telemetry.local_position(m.conn)
        m.target = (p.x + m.north0, p.y + m.east0, -p.z)
        m.fly_to(*m.target)
    service_all(conns, 0.3)  # proof of life before the mode switch
    setpoints = [gcs.flight.mode_for(m.conn, gcs.modes.SETPOINTS) for m in members]
    for m, mode in zip(members, setpoints):
        m.setpoint_mode = gcs.flight.set_mode(m.conn, mode).custom_mode
    print(" ".join(sorted(set(setpoints))), flush=True)

    legs = [(0.0, 0.0), (args.side, 0.0), (args.side, args.side), (0.0, args.side), (0.0, 0.0)]
    worst = 0.0
    for leg, (dn, de) in enumerate(legs):
        for m, (sn, se) in zip(members, slots):
            m.fly_to(centre_n + dn + sn, centre_e + de + se, args.height)
        service_all(conns, args.leg_time)
        for m, mode in zip(members, setpoints):
            beat = gcs.link.latest(m.conn, "HEARTBEAT")
            if beat is not None and beat.custom_mode != m.setpoint_mode:
                face = gcs.link.personality(m.conn)
                raise gcs.GcsError(f"system {m.conn.target_system} left {mode} for "
                                   f"{gcs.modes.vehicle_mode_name(face, beat.custom_mode)}")
        errors = [m.error() for m in members]
        worst = max(worst, *errors)
        print(f"leg {leg}: centre north {centre_n + dn:+.2f} east {centre_e + de:+.2f}; errors "
              + " ".join(f"{e:.3f}" for e in errors) + " m", flush=True)
    print(f"max formation error: {worst:.3f} m", flush=True)

    for m in members:
        gcs.flight.land(m.conn)
        gcs.offboard.stop_setpoints(m.conn)
    for m in members:
        gcs.telemetry.wait_disarmed(m.conn, 20.0 + 3.0 * args.height)
    print(f"{len(members)} vehicles landed and disarmed", flush=True)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
