#!/usr/bin/env python3
"""Render the figures of one flight as PNG files.

Usage:
    python gcs-scripts/plot_run.py RUN [--out OUTDIR] [--dpi 120]

RUN is a flight log or the directory holding one:

- ``DIR`` of ``rotorpilot sim SCENARIO.toml --out DIR``: its ``run.ulg`` (or, with ``--csv``,
  ``run.csv``) and ``summary.json``;
- ``DIR`` of ``rotorpilot run --log DIR``: its latest flight, ``DIR/log/*/*.ulg``;
- a ``.ulg`` file (``fly --log``, a downloaded log) or a ``run.csv`` file.

It writes into OUTDIR (default: RUN when it is a directory, else the file's directory):

    position.png  x, y, z and their references
    errors.png    position, velocity, attitude and angular-velocity errors
    attitude.png  roll, pitch, yaw and their references [deg]
    inputs.png    thrust u_T and torques tau_x, tau_y, tau_z (saturated ticks shaded)
    rotors.png    every rotor speed omega_i
    wrench.png    estimated external force/torque (solid) against what the estimator should see
                  (dashed): the true scripted wrench, with the unmodelled weight (m_r - m_e) g added
                  to f_z when the controller's mass is not the true one
    mass.png      estimated mass, with the true mass when the run says it

Values are plotted as logged: NED world, FRD body, SI units (z is positive down); empty CSV cells
(the control columns while the motors are off) are gaps. A signal that hardly moves is drawn on a
span of at least its quantity's resolution, so rounding noise does not look like oscillation.
Figures whose optional columns are absent (the estimator's) are skipped with a note on stderr. A
missing or malformed run exits with status 2 and ``error: PATH: ...``. Lines are decimated to at
most 20,000 points (min/max per bucket, so spikes survive) so that 10^6-row logs plot quickly.
"""
import argparse
import contextlib
import io
import json
import os
import pathlib
import re
import sys
import tempfile
import warnings

import numpy as np

MAX_POINTS = 20_000
MIN_ROTORS = 4
MAX_ROTORS = 16

XYZ = ("x", "y", "z")
POSITION = XYZ + tuple(f"{a}_ref" for a in XYZ)
ERRORS = ("ex", "ey", "ez", "evx", "evy", "evz", "eR_x", "eR_y", "eR_z", "ew_x", "ew_y", "ew_z")
ANGLES = ("roll", "pitch", "yaw")
ATTITUDE = ANGLES + tuple(f"{a}_ref" for a in ANGLES)
INPUTS = ("thrust", "tau_x", "tau_y", "tau_z")
REQUIRED = ("t",) + POSITION + ERRORS + ATTITUDE + INPUTS
WRENCH_HAT = ("fx_hat", "fy_hat", "fz_hat", "tx_hat", "ty_hat", "tz_hat")
WRENCH_TRUE = ("fx_true", "fy_true", "fz_true", "tx_true", "ty_true", "tz_true")
MASS = ("mass_hat",)
GRAVITY = 9.81
# Smallest span of a y axis per unit: a steadier signal is drawn centred on this span.
MIN_SPAN = {"m": 0.01, "m/s": 0.01, "deg": 0.1, "rad": 1e-3, "rad/s": 1e-2, "N": 1e-2, "N·m": 1e-3, "kg": 1e-2,
            "-": 1e-3}


class RunError(Exception):
    """A problem with the input files that ends the program with exit status 2."""


def parse_args(argv):
    """Parses the command line."""
    parser = argparse.ArgumentParser(description="Render PNG figures of a flight: a run.ulg, run.csv or flight "
                                                 "log, or the directory of sim --out / run --log holding one.")
    parser.add_argument("dir", type=pathlib.Path, metavar="RUN",
                        help="sim --out DIR, run --log DIR (its latest flight), or a .ulg / .csv file")
    parser.add_argument("--out", type=pathlib.Path, default=None,
                        help="where to write the PNGs (default: the run's directory)")
    parser.add_argument("--dpi", type=int, default=120, help="resolution of the PNGs (default: 120)")
    args = parser.parse_args(argv)
    if args.dpi <= 0:
        parser.error("--dpi must be positive")
    return args


def load_run(path):
    """Reads run.csv into (dict of column name -> float array, rotor column names); RunError if malformed."""
    try:
        with path.open("r", encoding="utf-8") as f:
            header = f.readline()
            if not header.strip():
                raise RunError(f"{path}: empty file (no header row)")
            names = [name.strip() for name in header.split(",")]
            if any(not name for name in names):
                raise RunError(f"{path}: empty column name in the header row")
            duplicates = sorted({name for name in names if names.count(name) > 1})
            if duplicates:
                raise RunError(f"{path}: duplicate column(s): {', '.join(duplicates)}")
            rotors = check_columns(names, path)
            # Empty cells (the control columns while the motors are off, the estimator's while it
            # is off) are gaps.
            text = EMPTY_CELL.sub("nan", f.read())
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)  # "input contained no data": reported below
                    data = np.loadtxt(io.StringIO(text), delimiter=",", dtype=np.float64, ndmin=2)
            except ValueError as exc:
                raise RunError(f"{path}: not a numeric CSV below the header: {exc}") from None
    except FileNotFoundError:
        raise RunError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise RunError(f"{path}: cannot read: {exc}") from None
    if data.shape[0] == 0:
        raise RunError(f"{path}: no data rows below the header")
    if data.shape[1] != len(names):
        raise RunError(f"{path}: {data.shape[1]} values per row but {len(names)} column names in the header")
    return {name: data[:, i] for i, name in enumerate(names)}, rotors


EMPTY_CELL = re.compile(r"(?<=,)(?=,|\r?$)|^(?=,)", re.MULTILINE)


def resolve_run(path):
    """(kind, file) of the run at `path`: ("ulog" | "csv", the file); RunError if none is there."""
    if path.is_file():
        return ("ulog" if path.suffix == ".ulg" else "csv"), path
    if not path.is_dir():
        raise RunError(f"{path}: no such file or directory")
    for name, kind in (("run.ulg", "ulog"), ("run.csv", "csv")):
        if (path / name).is_file():
            return kind, path / name
    flights = sorted(path.glob("log/*/*.ulg"))
    if flights:
        return "ulog", flights[-1]
    raise RunError(f"{path}: no run.ulg, run.csv or log/*/*.ulg (sim --out DIR or run --log DIR writes them)")


def load_any(path):
    """(columns, rotor names, what the run says of itself: summary.json or the ULog's info)."""
    kind, file = resolve_run(path)
    if kind == "csv":
        run, rotors = load_run(file)
        return run, rotors, load_summary(file.parent / "summary.json"), file
    from ulog_columns import load_ulog

    try:
        run, rotors, info = load_ulog(file)
    except (ValueError, OSError, IndexError, KeyError) as exc:
        raise RunError(f"{file}: not a flight log plot_run can read: {exc}") from None
    check_columns(run, file, rotors_required=False)
    summary = load_summary(file.parent / "summary.json")
    return run, rotors, {**info, **summary}, file


def rotor_columns(columns, path):
    """Returns the names omega_1..omega_n; raises RunError unless they are 4..16 and numbered without gaps."""
    numbers = []
    for name in columns:
        if name.startswith("omega_") and name[len("omega_"):].isdigit():
            numbers.append(int(name[len("omega_"):]))
    n = max(numbers, default=0)
    missing = [f"omega_{i}" for i in range(1, max(n, MIN_ROTORS) + 1) if i not in numbers]
    if missing:
        raise RunError(f"{path}: missing rotor column(s): {', '.join(missing)}")
    if n > MAX_ROTORS:
        raise RunError(f"{path}: {n} rotor columns, at most {MAX_ROTORS} are supported")
    return [f"omega_{i}" for i in range(1, n + 1)]


def check_columns(columns, path, rotors_required=True):
    """Raises RunError naming the required columns absent from the run; returns the rotor column names."""
    missing = [name for name in REQUIRED if name not in columns]
    if missing:
        raise RunError(f"{path}: missing column(s): {', '.join(missing)}")
    return rotor_columns(columns, path) if rotors_required else []


def optional_group(columns, names, path):
    """True if every column of an optional group is present, False if none is; RunError if only some are."""
    present = [name for name in names if name in columns]
    if present and len(present) != len(names):
        missing = [name for name in names if name not in columns]
        raise RunError(f"{path}: incomplete column group, missing: {', '.join(missing)}")
    return bool(present)


def load_summary(path):
    """Reads the optional summary.json; returns {} (with a note on stderr) if absent or unreadable."""
    if not path.exists():
        return {}
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        print(f"plot_run: ignoring {path}: {exc}", file=sys.stderr)
        return {}
    if not isinstance(summary, dict):
        print(f"plot_run: ignoring {path}: not a JSON object", file=sys.stderr)
        return {}
    return summary


def decimation_indices(y, max_points=MAX_POINTS):
    """Indices of at most max_points samples of y keeping each bucket's minimum and maximum (and both ends)."""
    n = len(y)
    if n <= max_points:
        return np.arange(n)
    buckets = max(1, (max_points - 2) // 2)
    size = -(-n // buckets)
    padded = np.concatenate([y, np.full(buckets * size - n, y[-1])]).reshape(buckets, size)
    base = np.arange(buckets) * size
    idx = np.concatenate([[0, n - 1], base + np.argmin(padded, axis=1), base + np.argmax(padded, axis=1)])
    return np.unique(np.minimum(idx, n - 1))


def plot_line(ax, t, y, max_points=MAX_POINTS, **style):
    """Plots y against t, decimated to at most max_points points (NaN samples are gaps)."""
    idx = decimation_indices(np.nan_to_num(y, nan=0.0), max_points)
    ax.plot(t[idx], y[idx], **style)


def min_span(ax, unit):
    """Widens the y axis to at least MIN_SPAN[unit] around the data, so a signal that hardly moves
    (rounding noise of 1e-17) is drawn flat instead of filling the axis."""
    floor = MIN_SPAN.get(unit)
    if floor is None:
        return
    low, high = ax.get_ylim()
    if high - low < floor:
        mid = 0.5 * (low + high)
        ax.set_ylim(mid - floor / 2, mid + floor / 2)


def unit_of(label):
    """The unit between the brackets at the end of an axis label ("u_T [N]" → "N")."""
    return label[label.rfind("[") + 1:label.rfind("]")] if label.endswith("]") else None


def finish_axes(axes):
    """Applies the minimum span of each axis' unit."""
    for ax in np.ravel(axes):
        unit = unit_of(ax.get_ylabel())
        if unit is not None:
            min_span(ax, unit)


def title_suffix(summary):
    """' (controller: ..., airframe: ...)' from the summary keys that are present, else ''."""
    parts = [f"{key}: {summary[key]}" for key in ("controller", "airframe") if key in summary]
    return f" ({', '.join(parts)})" if parts else ""


def new_figure(rows, cols=1, title="", row_height=2.2):
    """A pyplot-free figure with a grid of subplots sharing the time axis."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10 if cols == 1 else 12, 0.9 + row_height * rows), layout="constrained")
    axes = fig.subplots(rows, cols, sharex=True, squeeze=False)
    fig.suptitle(title)
    for ax in axes.flat:
        ax.grid(True, alpha=0.4)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    return fig, axes


def shade_saturated(ax, run):
    """Shades the time spans where the optional 'saturated' column is 1."""
    if "saturated" not in run:
        return
    t, sat = run["t"], run["saturated"] > 0.5
    if not sat.any():
        return
    idx = decimation_indices(sat.astype(np.float64))
    ax.fill_between(t[idx], 0, 1, where=sat[idx], step="post", color="tab:red", alpha=0.12,
                    transform=ax.get_xaxis_transform(), label="saturated", linewidth=0)


def fig_position(run, summary):
    """x, y, z and references, three stacked subplots."""
    fig, axes = new_figure(3, title="Position" + title_suffix(summary))
    labels = ("x (NED, north) [m]", "y (NED, east) [m]", "z (NED, down) [m]")
    for ax, axis, label in zip(axes[:, 0], XYZ, labels):
        plot_line(ax, run["t"], run[axis], label=axis)
        plot_line(ax, run["t"], run[f"{axis}_ref"], linestyle="--", label=f"{axis}_ref")
        ax.set_ylabel(label)
        ax.legend(loc="best", fontsize="small")
    finish_axes(axes)
    return fig


def fig_errors(run, summary):
    """Position, velocity, attitude and angular-velocity errors, four subplots."""
    fig, axes = new_figure(4, title="Tracking errors" + title_suffix(summary))
    groups = (
        (("ex", "ey", "ez"), "e_p [m]"),
        (("evx", "evy", "evz"), "e_v [m/s]"),
        (("eR_x", "eR_y", "eR_z"), "e_R [-]"),
        (("ew_x", "ew_y", "ew_z"), "e_ω [rad/s]"),
    )
    for ax, (names, label) in zip(axes[:, 0], groups):
        for name in names:
            plot_line(ax, run["t"], run[name], label=name)
        ax.set_ylabel(label)
        ax.legend(loc="best", fontsize="small", ncol=3)
    finish_axes(axes)
    return fig


def fig_attitude(run, summary):
    """Roll, pitch, yaw and their references in degrees."""
    fig, axes = new_figure(3, title="Attitude (ZYX Euler angles, FRD body)" + title_suffix(summary))
    for ax, angle in zip(axes[:, 0], ANGLES):
        plot_line(ax, run["t"], np.degrees(run[angle]), label=angle)
        plot_line(ax, run["t"], np.degrees(run[f"{angle}_ref"]), linestyle="--", label=f"{angle}_ref")
        ax.set_ylabel(f"{angle} [deg]")
        ax.legend(loc="best", fontsize="small")
    finish_axes(axes)
    return fig


def fig_inputs(run, summary):
    """Thrust and body torques; saturated spans shaded if logged."""
    fig, axes = new_figure(4, title="Control inputs" + title_suffix(summary))
    labels = ("u_T [N]", "τ_x [N·m]", "τ_y [N·m]", "τ_z [N·m]")
    for ax, name, label in zip(axes[:, 0], INPUTS, labels):
        shade_saturated(ax, run)
        plot_line(ax, run["t"], run[name], label=name)
        ax.set_ylabel(label)
    if "saturated" in run and (run["saturated"] > 0.5).any():
        axes[0, 0].legend(loc="best", fontsize="small")
    finish_axes(axes)
    return fig


def fig_rotors(run, summary, rotors, unit="ω_i [rad/s]"):
    """Every rotor speed on one axis."""
    fig, axes = new_figure(1, title=f"Rotor speeds, {len(rotors)} rotors" + title_suffix(summary), row_height=4.5)
    ax = axes[0, 0]
    shade_saturated(ax, run)
    for name in rotors:
        plot_line(ax, run["t"], run[name], label=name, linewidth=1)
    ax.set_ylabel(unit)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", ncol=1 if len(rotors) <= 8 else 2)
    finish_axes(axes)
    return fig


def mass_mismatch_force(summary):
    """(m_r - m_e) g [N]: the weight the controller does not know of, which the estimator sees as
    an external force along +z (NED down); 0 when the run does not say its masses."""
    if "mass_mismatch_force_n" in summary:
        return float(summary["mass_mismatch_force_n"])
    true, believed = summary.get("true_mass_kg"), summary.get("believed_mass_kg")
    if isinstance(true, (int, float)) and isinstance(believed, (int, float)):
        return (true - believed) * GRAVITY
    return 0.0


def fig_wrench(run, summary, has_truth):
    """Estimated external forces (left) and torques (right), estimate solid; dashed, what the
    estimator should converge to: the true wrench, plus the unmodelled weight on f_z."""
    fig, axes = new_figure(3, 2, title="External wrench estimate" + title_suffix(summary))
    mismatch = mass_mismatch_force(summary)
    for k, hat in enumerate(WRENCH_HAT):
        ax = axes[k % 3, k // 3]
        plot_line(ax, run["t"], run[hat], label=hat, color=f"C{k % 3}")
        if has_truth:
            expected, label = run[WRENCH_TRUE[k]], WRENCH_TRUE[k]
            if hat == "fz_hat" and mismatch != 0.0:
                expected = expected + mismatch
                label = f"fz_true + (m_r − m_e) g = fz_true + {mismatch:.3g} N"
            plot_line(ax, run["t"], expected, label=label, color="black", linestyle="--", linewidth=1)
        axis = hat[1]
        ax.set_ylabel(f"f_{axis} [N]" if k < 3 else f"τ_{axis} [N·m]")
        ax.legend(loc="best", fontsize="small")
    axes[0, 0].set_title("force (NED world)")
    axes[0, 1].set_title("torque (FRD body)")
    finish_axes(axes)
    return fig


def fig_mass(run, summary):
    """Estimated mass, with the true mass from summary.json if known."""
    fig, axes = new_figure(1, title="Mass estimate" + title_suffix(summary), row_height=3.5)
    ax = axes[0, 0]
    plot_line(ax, run["t"], run["mass_hat"], label="mass_hat")
    true_mass = summary.get("true_mass_kg")
    if isinstance(true_mass, (int, float)) and not isinstance(true_mass, bool):
        ax.axhline(true_mass, color="black", linestyle="--", linewidth=1, label=f"true mass {true_mass:g} kg")
    ax.set_ylabel("mass [kg]")
    ax.legend(loc="best", fontsize="small")
    finish_axes(axes)
    return fig


def build_figures(run, summary, rotors, path):
    """Yields (file name, figure builder) for every figure the run's columns allow; notes skips on stderr."""
    yield "position.png", lambda: fig_position(run, summary)
    yield "errors.png", lambda: fig_errors(run, summary)
    yield "attitude.png", lambda: fig_attitude(run, summary)
    yield "inputs.png", lambda: fig_inputs(run, summary)
    if rotors:
        unit = "ω_i [rad/s]" if path.suffix == ".csv" else "ω_i / ω_max, commanded [-]"
        yield "rotors.png", lambda: fig_rotors(run, summary, rotors, unit)
    else:
        print("plot_run: skipping rotors.png: no rotor speeds in the log", file=sys.stderr)
    if optional_group(run, WRENCH_HAT, path) and not np.all(np.isnan(run["fx_hat"])):
        has_truth = optional_group(run, WRENCH_TRUE, path)
        if not has_truth:
            print(f"plot_run: wrench.png without truth: no {', '.join(WRENCH_TRUE)} columns", file=sys.stderr)
        yield "wrench.png", lambda: fig_wrench(run, summary, has_truth)
    else:
        print(f"plot_run: skipping wrench.png: no estimate ({', '.join(WRENCH_HAT)}: the estimator was off)",
              file=sys.stderr)
    if optional_group(run, MASS, path) and not np.all(np.isnan(run["mass_hat"])):
        yield "mass.png", lambda: fig_mass(run, summary)
    else:
        print("plot_run: skipping mass.png: no mass estimate (mass_hat)", file=sys.stderr)


def writable_dir(path):
    """True if path exists (or can be created) and is writable."""
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    return os.access(path, os.W_OK | os.X_OK)


@contextlib.contextmanager
def matplotlib_agg():
    """Selects the Agg backend, with MPLCONFIGDIR in a temporary directory if the home is not writable."""
    with contextlib.ExitStack() as stack:
        if "MPLCONFIGDIR" not in os.environ:
            config_home = pathlib.Path(os.environ.get("XDG_CONFIG_HOME") or pathlib.Path.home() / ".config")
            cache_home = pathlib.Path(os.environ.get("XDG_CACHE_HOME") or pathlib.Path.home() / ".cache")
            if not (writable_dir(config_home / "matplotlib") and writable_dir(cache_home / "matplotlib")):
                os.environ["MPLCONFIGDIR"] = stack.enter_context(tempfile.TemporaryDirectory(prefix="mplconfig-"))
        os.environ["MPLBACKEND"] = "Agg"
        import matplotlib

        matplotlib.use("Agg")
        yield


def main(argv=None):
    """Entry point: returns the exit status (0 ok, 2 bad input)."""
    args = parse_args(argv)
    try:
        run, rotors, summary, path = load_any(args.dir)
        figures = list(build_figures(run, summary=summary, rotors=rotors, path=path))
    except RunError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out_dir = args.out if args.out is not None else (args.dir if args.dir.is_dir() else path.parent)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        print(f"error: {out_dir}: cannot create the output directory: {exc}", file=sys.stderr)
        return 2
    with matplotlib_agg():
        for name, build in figures:
            fig = build()
            target = out_dir / name
            try:
                fig.savefig(target, dpi=args.dpi)
            except OSError as exc:
                print(f"error: {target}: cannot write: {exc}", file=sys.stderr)
                return 2
            print(target)
    return 0


if __name__ == "__main__":
    sys.exit(main())
