#!/usr/bin/env python3
"""Plot a sweep's metrics against one of its axes.

Usage:
    python gcs-scripts/plot_sweep.py DIR [--x FIELD] [--y METRIC ...] [--hue FIELD] [--out PNG]

DIR holds the ``results.parquet`` of ``rotorpilot sweep SWEEP.toml --out DIR`` or of
``python -m rotorpilot_gcs.campaign SWEEP.toml --out DIR`` (one row per run: run, point, seed,
the axes, status, error, the metrics; docs/sweep.md). One panel per metric (``--y``, repeatable;
default: those of DEFAULT_METRICS the file has, else its first numeric metrics), each against the
axis ``--x`` (default: the first axis), one colour per value of ``--hue`` (default: the second
axis, if any; ``--hue none`` for one colour). Every good run is a dot and each colour's mean per
x value a line. A run that did not go well (status other than ``ok``, or an ``exit`` other than
``complete``) is a red ×: at its value when it has one, else along the bottom of the panel. For
homework exercise 4, say: convergence or tracking error against the estimator order, one colour
per sample time, the runs that fail at Ts = 1 ms marked.

The figure goes to --out (default DIR/sweep.png); its path is printed. A missing file or an
unknown column exits with status 2 and ``error: ...``.
"""
import argparse
import math
import pathlib
import sys

#: Metrics plotted by default, those present (the first ones for the exercise 4 trade-offs).
DEFAULT_METRICS = (
    "estimate.convergence_time_s",
    "estimate.force_overshoot_pct",
    "final_position_error_norm_m",
    "max_tilt_deg",
)
#: Panels when no default metric is present: the first numeric metrics.
MAX_PANELS = 6
NON_METRICS = ("run", "point", "seed", "status", "error")
DPI = 120


class PlotError(Exception):
    """A problem reported as ``error: ...`` with exit status 2."""


def load(directory):
    """The rows of DIR/results.parquet (a pyarrow table)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = pathlib.Path(directory) / "results.parquet"
    if not path.is_file():
        raise PlotError(f"{path}: no such file (run `rotorpilot sweep SWEEP.toml --out {directory}` first)")
    try:
        return pq.read_table(path)
    except (OSError, pa.ArrowException) as e:
        raise PlotError(f"{path}: {e}") from None


def axes_of(table):
    """The axis columns: those between ``seed`` and ``status`` (the results' column order)."""
    names = table.column_names
    if "seed" not in names or "status" not in names:
        raise PlotError("not a sweep's results: no seed or status column")
    return names[names.index("seed") + 1:names.index("status")]


def numeric(table, name):
    """Whether column `name` holds numbers (integers or floats, not flags)."""
    import pyarrow as pa

    kind = table.schema.field(name).type
    return pa.types.is_integer(kind) or pa.types.is_floating(kind)


def default_metrics(table):
    """DEFAULT_METRICS the table has as numbers, else its first MAX_PANELS numeric metrics."""
    axes = set(axes_of(table))
    present = [m for m in DEFAULT_METRICS if m in table.column_names and numeric(table, m)]
    if present:
        return present
    others = [n for n in table.column_names if n not in axes and n not in NON_METRICS and numeric(table, n)]
    return others[:MAX_PANELS]


def bad_rows(table):
    """Per row, whether the run went wrong: status other than ok, or exit other than complete."""
    status = table.column("status").to_pylist()
    exits = table.column("exit").to_pylist() if "exit" in table.column_names else [None] * table.num_rows
    return [s != "ok" or (e is not None and e != "complete") for s, e in zip(status, exits)]


def positions(values):
    """x positions of `values` and tick labels: the numbers themselves, or the categories (names,
    flags) in order of first appearance at 0, 1, 2…"""
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values if v is not None):
        return [math.nan if v is None else float(v) for v in values], None
    categories = list(dict.fromkeys(values))
    return [float(categories.index(v)) for v in values], [str(c) for c in categories]


def check_column(table, name, what):
    """`PlotError` naming the columns when `name` is not one."""
    if name not in table.column_names:
        raise PlotError(f"no {what} column {name!r}; the file has: {', '.join(table.column_names)}")


def plot(table, x, metrics, hue, out):
    """Draws one panel per metric against `x`, coloured by `hue` (None: one colour), to `out`.
    Against an axis each colour's mean per x value is a line; against a metric (a trade-off, such
    as convergence time against overshoot) the runs are dots only."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs, labels = positions(table.column(x).to_pylist())
    mean_lines = x in axes_of(table)
    groups = table.column(hue).to_pylist() if hue else [None] * table.num_rows
    order = list(dict.fromkeys(groups))
    bad = bad_rows(table)
    fig, panels = plt.subplots(len(metrics), 1, figsize=(7.5, 2.6 * len(metrics) + 0.6), squeeze=False,
                               sharex=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, metric in zip(panels[:, 0], metrics):
        ys = [math.nan if v is None else float(v) for v in table.column(metric).to_pylist()]
        for k, group in enumerate(order):
            colour = colours[k % len(colours)]
            good = [(xv, yv) for xv, yv, g, b in zip(xs, ys, groups, bad)
                    if g == group and not b and math.isfinite(yv) and math.isfinite(xv)]
            name = f"{hue} = {group}" if hue else None
            if good and not mean_lines:
                ax.plot([p[0] for p in good], [p[1] for p in good], "o", color=colour, alpha=0.6, markersize=4,
                        label=name)
            elif good:
                ax.plot([p[0] for p in good], [p[1] for p in good], "o", color=colour, alpha=0.5, markersize=4)
                means = {}
                for xv, yv in good:
                    means.setdefault(xv, []).append(yv)
                line_x = sorted(means)
                ax.plot(line_x, [sum(means[v]) / len(means[v]) for v in line_x], "-", color=colour, label=name)
            elif name:
                ax.plot([], [], "-", color=colour, label=name)
        marked_value = [(xv, yv) for xv, yv, b in zip(xs, ys, bad) if b and math.isfinite(yv)]
        marked_none = [xv for xv, yv, b in zip(xs, ys, bad) if b and not math.isfinite(yv)]
        if marked_value:
            ax.plot([p[0] for p in marked_value], [p[1] for p in marked_value], "x", color="red", markersize=8,
                    mew=2)
        if marked_none:
            # No value (the run failed before its metrics): along the bottom of the panel.
            ax.plot(marked_none, [0.04] * len(marked_none), "x", color="red", markersize=8, mew=2,
                    transform=ax.get_xaxis_transform(), clip_on=False)
        if marked_value or marked_none:
            ax.plot([], [], "x", color="red", mew=2, label="not ok / not complete")
        ax.set_ylabel(metric, fontsize=8)
        ax.grid(True, alpha=0.3)
        if hue or marked_value or marked_none:
            ax.legend(fontsize=7, loc="best")
    bottom = panels[-1, 0]
    bottom.set_xlabel(x)
    if labels is not None:
        bottom.set_xticks(range(len(labels)), labels)
    fig.suptitle(f"{table.num_rows} runs, {sum(bad)} not ok", fontsize=10)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def main(argv=None):
    """Runs the command line; the exit status."""
    parser = argparse.ArgumentParser(description="Plot a sweep's metrics against one of its axes.")
    parser.add_argument("dir", type=pathlib.Path, help="directory holding results.parquet")
    parser.add_argument("--x", help="the column along x: an axis (default: the first), or a metric for a "
                                    "trade-off (dots only, no mean lines)")
    parser.add_argument("--y", action="append",
                        help="a metric to plot (repeatable; default: those of DEFAULT_METRICS present)")
    parser.add_argument("--hue",
                        help="one colour per value of this column (default: the second axis; none: one colour)")
    parser.add_argument("--out", type=pathlib.Path, help="the PNG (default DIR/sweep.png)")
    args = parser.parse_args(argv)
    try:
        table = load(args.dir)
        axes = axes_of(table)
        x = args.x or (axes[0] if axes else "run")
        check_column(table, x, "x")
        hue = args.hue if args.hue is not None else (axes[1] if len(axes) > 1 and axes[1] != x else None)
        hue = None if hue in ("", "none") else hue
        if hue:
            check_column(table, hue, "hue")
        metrics = args.y or default_metrics(table)
        if not metrics:
            raise PlotError("no numeric metric to plot; name one with --y")
        for metric in metrics:
            check_column(table, metric, "metric")
            if not numeric(table, metric):
                raise PlotError(f"metric {metric!r} is not numeric ({table.schema.field(metric).type})")
        out = args.out or args.dir / "sweep.png"
        plot(table, x, metrics, hue, out)
    except (PlotError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
