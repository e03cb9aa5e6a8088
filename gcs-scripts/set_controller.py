#!/usr/bin/env python3
"""Select the control law, the wrench estimator, compensation and gains of a running autopilot.

Usage:
    python gcs-scripts/set_controller.py {geometric,hierarchical,passivity}
        [--estimator-order R] [--ripple-db RP] [--wp W] [--compensation on|off]
        [--gain NAME=VALUE ...] [--connection udpin:0.0.0.0:14550] [--timeout S]

Sets, in this order and each checked against the echoed PARAM_VALUE: RP_CTRL (INT32: 0 geometric,
1 hierarchical, 2 passivity), RP_EST_RIPPLE [dB], RP_EST_WP [rad/s], RP_EST_ORDER (INT32, 0 = off),
RP_COMP (INT32) and every --gain (REAL32; NAME with or without the RP_ prefix, e.g.
GEO_KP_Z=30). The autopilot switches laws bumplessly in flight. A refused value (the echo keeps
the old one) stops the script with ``error:`` and the autopilot's reason, exit status 1.
"""
import math

import rotorpilot_gcs as gcs

CONTROLLERS = {"geometric": 0, "hierarchical": 1, "passivity": 2}


def gain(text):
    name, sep, value = text.partition("=")
    name = name.strip().upper()
    if not sep or not name:
        raise ValueError(text)
    if not name.startswith("RP_"):
        name = "RP_" + name
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(text)
    return name, v


gain.__name__ = "NAME=VALUE"


def main(argv=None):
    p = gcs.cli.parser(__doc__.split("\n\n")[0])
    p.add_argument("controller", choices=sorted(CONTROLLERS, key=CONTROLLERS.get), help="control law (RP_CTRL)")
    p.add_argument("--estimator-order", type=int, default=None, metavar="R",
                   help="wrench estimator order, 0 = off (RP_EST_ORDER)")
    p.add_argument("--ripple-db", type=float, default=None, metavar="RP", help="Chebyshev ripple [dB] (RP_EST_RIPPLE)")
    p.add_argument("--wp", type=float, default=None, metavar="W", help="passband edge [rad/s] (RP_EST_WP)")
    p.add_argument("--compensation", choices=["on", "off"], default=None,
                   help="subtract the estimated wrench (RP_COMP)")
    p.add_argument("--gain", type=gain, action="append", default=[], metavar="NAME=VALUE",
                   help="a REAL32 RP_* gain, e.g. GEO_KP_Z=30 (repeatable)")
    args = p.parse_args(argv)
    if args.estimator_order is not None and args.estimator_order < 0:
        p.error("--estimator-order must be >= 0")

    settings = [("RP_CTRL", CONTROLLERS[args.controller], True)]
    if args.ripple_db is not None:
        settings.append(("RP_EST_RIPPLE", args.ripple_db, False))
    if args.wp is not None:
        settings.append(("RP_EST_WP", args.wp, False))
    if args.estimator_order is not None:
        settings.append(("RP_EST_ORDER", args.estimator_order, True))
    if args.compensation is not None:
        settings.append(("RP_COMP", int(args.compensation == "on"), True))
    settings += [(name, value, False) for name, value in args.gain]

    conn = gcs.connect(args.connection, args.timeout)
    for name, value, int32 in settings:
        got = gcs.params.param_set(conn, name, value, int32=int32)
        print(f"{name} = {got:g}" if not int32 else f"{name} = {got}", flush=True)
    return 0


if __name__ == "__main__":
    gcs.cli.script_main(main)
