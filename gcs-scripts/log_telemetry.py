#!/usr/bin/env python3
"""Record the autopilot's telemetry into one CSV file, one row per received message.

Usage:
    python gcs-scripts/log_telemetry.py --out FILE.csv [--duration S] [--connection udpin:0.0.0.0:14550]
                                        [--timeout S]

Columns: ``t_wall, msg, t_boot, f1, f2, f3, f4, f5, f6`` where t_wall is the receive time (Unix
seconds), msg the message (for the estimator its name), t_boot the autopilot's time since boot [s]
(empty for HEARTBEAT) and f1..f6 depend on msg (unused fields empty):

    ATTITUDE             roll, pitch, yaw [rad], rollspeed, pitchspeed, yawspeed [rad/s]
    LOCAL_POSITION_NED   x, y, z [m], vx, vy, vz [m/s]                      (NED from home)
    GLOBAL_POSITION_INT  lat, lon [deg], alt [m AMSL], relative_alt [m], vx, vy [m/s]
    HEARTBEAT            mode (e.g. AUTO.LOITER), armed (0/1), custom_mode, system_status
    EXT_F                x, y, z: estimated external force, world NED [N]  (DEBUG_VECT)
    EXT_T                x, y, z: estimated external torque, body FRD [N·m] (DEBUG_VECT)
    EXT_MASS             value: mass estimate [kg]                          (NAMED_VALUE_FLOAT)

The estimator streams only while it runs (RP_EST_ORDER > 0, see set_controller.py) and the vehicle
flies. Rates: ATTITUDE 15 Hz, GLOBAL_POSITION_INT 5 Hz, LOCAL_POSITION_NED and HEARTBEAT 1 Hz,
the estimator 10 Hz. The script stops after --duration seconds and prints the row count per
message; exit status 1 if no autopilot answers.
"""
import csv
import time

import rotorpilot_gcs as gcs

HEADER = ["t_wall", "msg", "t_boot", "f1", "f2", "f3", "f4", "f5", "f6"]
ESTIMATOR = ("EXT_F", "EXT_T", "EXT_MASS")


def row(m):
    """(msg, t_boot, fields) of a logged message, or None for the others."""
    kind = m.get_type()
    if kind == "ATTITUDE":
        return kind, f"{m.time_boot_ms * 1e-3:.3f}", [m.roll, m.pitch, m.yaw, m.rollspeed, m.pitchspeed, m.yawspeed]
    if kind == "LOCAL_POSITION_NED":
        return kind, f"{m.time_boot_ms * 1e-3:.3f}", [m.x, m.y, m.z, m.vx, m.vy, m.vz]
    if kind == "GLOBAL_POSITION_INT":
        return kind, f"{m.time_boot_ms * 1e-3:.3f}", [m.lat * 1e-7, m.lon * 1e-7, m.alt * 1e-3, m.relative_alt * 1e-3,
                                             m.vx * 1e-2, m.vy * 1e-2]
    if kind == "HEARTBEAT" and m.get_srcComponent() == 1:
        return kind, "", [gcs.mode_name(m.custom_mode), int(gcs.telemetry.is_armed(m)), m.custom_mode, m.system_status]
    if kind == "DEBUG_VECT" and m.name in ESTIMATOR:
        return m.name, f"{m.time_usec * 1e-6:.6f}", [m.x, m.y, m.z]
    if kind == "NAMED_VALUE_FLOAT" and m.name in ESTIMATOR:
        return m.name, f"{m.time_boot_ms * 1e-3:.3f}", [m.value]
    return None


def main(argv=None):
    p = gcs.cli.parser(__doc__.split("\n\n")[0])
    p.add_argument("--out", required=True, help="CSV file to write")
    p.add_argument("--duration", type=float, default=10.0, help="recording time [s] (default 10)")
    args = p.parse_args(argv)
    if args.duration <= 0:
        p.error("--duration must be > 0")

    conn = gcs.connect(args.connection, args.timeout)
    counts = {}
    with open(args.out, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(HEADER)

        def record(m):
            r = row(m)
            if r is not None:
                kind, t_boot, fields = r
                out.writerow([f"{time.time():.6f}", kind, t_boot, *fields])
                counts[kind] = counts.get(kind, 0) + 1

        gcs.link.sleep(conn, args.duration, record)
    total = sum(counts.values())
    print(f"wrote {total} rows to {args.out}: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), flush=True)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
