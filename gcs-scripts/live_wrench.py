#!/usr/bin/env python3
"""Print the autopilot's live external-wrench estimate and optionally plot it.

Usage:
    python gcs-scripts/live_wrench.py [--duration S] [--plot FILE.png] [--connection udpin:0.0.0.0:14550]
                                      [--timeout S]

Prints one line per estimate as it arrives: DEBUG_VECT ``EXT_F`` (external force, world NED [N]),
``EXT_T`` (external torque, body FRD [N·m]) and NAMED_VALUE_FLOAT ``EXT_MASS`` (mass estimate
[kg]), each with the autopilot's time since boot. The autopilot streams them at 10 Hz only while
the estimator runs (RP_EST_ORDER > 0, see set_controller.py) and the vehicle flies; a note says so
when nothing arrives. Without --duration it runs until Ctrl-C. With --plot it saves a figure
(force, torque, mass against time; matplotlib with the Agg backend) at the end.
"""
import time

import rotorpilot_gcs as gcs

NAMES = ("EXT_F", "EXT_T", "EXT_MASS")


def plot(path, series):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
    for ax, name, unit in zip(axes[:2], ("EXT_F", "EXT_T"), ("force, world NED [N]", "torque, body FRD [N·m]")):
        data = series[name]
        for i, axis in enumerate("xyz"):
            ax.plot([d[0] for d in data], [d[1][i] for d in data], label=axis)
        ax.set_ylabel(unit)
        ax.legend(loc="upper right")
        ax.grid(True)
    mass = series["EXT_MASS"]
    axes[2].plot([d[0] for d in mass], [d[1][0] for d in mass], color="k")
    axes[2].set_ylabel("mass estimate [kg]")
    axes[2].set_xlabel("time since boot [s]")
    axes[2].grid(True)
    fig.suptitle("external wrench estimate")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None):
    p = gcs.cli.parser(__doc__.split("\n\n")[0])
    p.add_argument("--duration", type=float, default=None, help="stop after S seconds (default: until Ctrl-C)")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="save a figure of the estimate at the end")
    args = p.parse_args(argv)
    if args.duration is not None and args.duration <= 0:
        p.error("--duration must be > 0")
    # Before listening, not after the flight: a missing matplotlib must not cost the data.
    if args.plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            p.error("--plot needs matplotlib: install it (pip install matplotlib, or the pinned "
                    "gcs-scripts/requirements.txt) or leave --plot out")

    conn = gcs.connect(args.connection, args.timeout)
    series = {name: [] for name in NAMES}
    quiet_note = [time.monotonic()]

    def show(m):
        kind = m.get_type()
        if kind == "DEBUG_VECT" and m.name in ("EXT_F", "EXT_T"):
            t, v = m.time_usec * 1e-6, (m.x, m.y, m.z)
            unit = "N" if m.name == "EXT_F" else "N·m"
            print(f"{t:9.3f} {m.name:8s} {v[0]:+9.4f} {v[1]:+9.4f} {v[2]:+9.4f} {unit}", flush=True)
        elif kind == "NAMED_VALUE_FLOAT" and m.name == "EXT_MASS":
            t, v = m.time_boot_ms * 1e-3, (m.value,)
            print(f"{t:9.3f} {m.name:8s} {v[0]:9.4f} kg", flush=True)
        else:
            return
        series[m.name].append((t, v))
        quiet_note[0] = time.monotonic()

    def tick(m):
        if m is not None:
            show(m)
        if time.monotonic() - quiet_note[0] > 5.0:
            print("no estimate for 5 s: is RP_EST_ORDER > 0 and the vehicle flying?", flush=True)
            quiet_note[0] = time.monotonic()

    try:
        if args.duration is None:
            while True:
                tick(gcs.link.recv(conn, 1.0))
        else:
            deadline = time.monotonic() + args.duration
            while (remaining := deadline - time.monotonic()) > 0:
                tick(gcs.link.recv(conn, min(remaining, 1.0)))
    except KeyboardInterrupt:
        pass
    counts = ", ".join(f"{name} {len(series[name])}" for name in NAMES)
    print(f"received {counts}", flush=True)
    if args.plot:
        plot(args.plot, series)
        print(f"wrote {args.plot}", flush=True)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
