#!/usr/bin/env python3
"""Reproduce the studies of homework exercises 4 (wrench estimator) and 5 (geometric controller).

Usage:
    python gcs-scripts/homework_study.py --out DIR [--only ex4|ex5] [--binary PATH]

The binary defaults to $ROTORPILOT_BIN, else target/release/rotorpilot.

Exercise 4: flies scenarios/ex4_estimator.toml once (``rotorpilot sim ... --out DIR/ex4/flight``),
then runs ``rotorpilot estimate`` over that flight's ULog (DIR/ex4/flight/run.ulg) for each of the
six estimator designs of DESIGNS (per-sample estimates in DIR/ex4/estimates/testK.csv) and writes

    DIR/ex4_forces.png   f̂x, f̂y, f̂z of the six designs, one panel each, truth dashed
    DIR/ex4_torques.png  τ̂x, τ̂y, τ̂z likewise
    DIR/ex4_tests.json   per design: order, ripple, Wp, final estimate, mass estimate
                         m_e + f̂z/g, and the settling time of f̂x (2 % band) or "does not settle"

and prints the table. The truth is the log's external_wrench_truth: the scripted force and torque,
with the unmodelled weight (m_r − m_e) g added to the down force.

Exercise 5: flies scenarios/ex5_geometric.toml (``--out DIR/ex5/flight``), reads its run.ulg with
pyulog and writes DIR/ex5_{position,velocity,attitude,rate}_errors.png, ex5_thrust.png,
ex5_torques.png, ex5_final_configuration.png and ex5_summary.json (final position error, final
thrust against m g, largest errors).

Progress goes to stderr, tables to stdout. A missing binary, a failing run or an unreadable log
prints ``error: ...`` naming it on stderr and exits with status 2.
"""
import argparse
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import tomllib

import homework_figures
import plot_run
import rotorpilot_gcs

ROOT = pathlib.Path(__file__).resolve().parents[1]
EX4_SCENARIO = ROOT / "scenarios" / "ex4_estimator.toml"
EX5_SCENARIO = ROOT / "scenarios" / "ex5_geometric.toml"
AIRFRAMES = ROOT / "airframes"
DPI = 120
RUN_TIMEOUT_S = 600
SETTLING_BAND = 0.02  # [-] of the true value
WRENCH = ("fx", "fy", "fz", "tx", "ty", "tz")

# (test, order r, ripple [dB], passband edge Wp [rad/s], note)
DESIGNS = (
    (1, 1, 3.0, 2.0, ""),
    (2, 1, 3.0, 20.0, "test 1 with ten times the bandwidth"),
    (3, 1, 20.0, 20.0, "test 2 with 20 dB ripple"),
    (4, 7, 3.0, 2.0, "test 1 at order 7"),
    (5, 7, 1.0, 5.0, "not given by the homework, which asks for more bandwidth and less ripple than test 4"),
    (6, 13, 1.0, 5.0, "test 5 at order 13"),
)


class StudyError(Exception):
    """A problem that ends the study with exit status 2."""


def progress(text):
    """One progress line on stderr."""
    print(f"homework_study: {text}", file=sys.stderr, flush=True)


def parse_args(argv):
    """Parses the command line."""
    parser = argparse.ArgumentParser(description="Reproduce homework exercises 4 and 5 with rotorpilot.")
    parser.add_argument("--out", type=pathlib.Path, required=True, help="output directory (created if missing)")
    parser.add_argument("--only", choices=("ex4", "ex5"), help="run one exercise only")
    parser.add_argument("--binary", type=pathlib.Path, default=None,
                        help="rotorpilot binary (default: $ROTORPILOT_BIN, else target/release/rotorpilot, else PATH)")
    return parser.parse_args(argv)


def find_binary(arg):
    """The rotorpilot binary to run (rotorpilot_gcs.find_binary: --binary, $ROTORPILOT_BIN, the
    checkout's build, PATH); StudyError if it is missing or not executable."""
    try:
        binary = rotorpilot_gcs.find_binary(arg, fallback=rotorpilot_gcs.process.checkout_binary())
    except FileNotFoundError as exc:
        raise StudyError(f"{exc} (or pass --binary)") from None
    if not os.access(binary, os.X_OK):
        raise StudyError(f"rotorpilot binary {binary} is not executable")
    return binary


def run_binary(binary, *args):
    """Runs `binary args`, returns its stdout; StudyError naming the command if it fails."""
    cmd = [str(binary), *map(str, args)]
    shown = " ".join(["rotorpilot", *cmd[1:]])
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=RUN_TIMEOUT_S, check=False)
    except (OSError, subprocess.SubprocessError) as exc:
        raise StudyError(f"`{shown}` could not run: {exc}") from None
    if proc.returncode != 0:
        detail = proc.stderr.strip().splitlines()[-3:]
        raise StudyError(f"`{shown}` failed with exit status {proc.returncode}"
                         + (": " + " | ".join(detail) if detail else ""))
    return proc.stdout


def parse_json(text, what):
    """The JSON object `text`; StudyError naming `what` if it is not one."""
    try:
        value = json.loads(text)
    except ValueError as exc:
        raise StudyError(f"{what}: not JSON: {exc}") from None
    if not isinstance(value, dict):
        raise StudyError(f"{what}: not a JSON object")
    return value


def fly(binary, scenario, out_dir):
    """Flies `scenario` into out_dir (run.ulg, summary.json); returns the summary."""
    progress(f"flying {scenario.name} into {out_dir}")
    stdout = run_binary(binary, "sim", scenario, "--out", out_dir)
    summary = parse_json(stdout, f"rotorpilot sim {scenario.name}")
    if summary.get("exit") != "complete":
        raise StudyError(f"rotorpilot sim {scenario.name}: the flight ended with exit {summary.get('exit')!r}")
    return summary


def read_toml(path):
    """The TOML table in path; StudyError if unreadable."""
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise StudyError(f"{path}: cannot read: {exc}") from None


def merge(base, over):
    """Deep merge of TOML tables (tables key by key, anything else replaced), as scenarios do."""
    out = dict(base)
    for key, value in over.items():
        out[key] = merge(out[key], value) if isinstance(out.get(key), dict) and isinstance(value, dict) else value
    return out


def scenario_airframe(scenario):
    """(what `--airframe` takes, the airframe table with the scenario's overrides merged in)."""
    spec = read_toml(scenario).get("airframe", {})
    if "preset" in spec:
        name, path = spec["preset"], AIRFRAMES / f"{spec['preset']}.toml"
    elif "path" in spec:
        path = scenario.parent / spec["path"]
        name = path
    else:
        raise StudyError(f"{scenario}: [airframe] names neither a preset nor a path")
    return name, merge(read_toml(path), spec.get("overrides", {}))


def believed_inertia(airframe, scenario):
    """The principal inertia the flight controller believes: [fc] inertia, else the vehicle's [kg·m²]."""
    inertia = airframe.get("fc", {}).get("inertia", airframe.get("vehicle", {}).get("inertia"))
    if not (isinstance(inertia, list) and len(inertia) == 3):
        raise StudyError(f"{scenario}: its airframe has no vehicle inertia [Ixx, Iyy, Izz]")
    return [float(v) for v in inertia]


def read_topics(path, topics):
    """{topic: {field: array}} of the first instance of each topic in a ULog, plus 't' [s]."""
    try:
        from pyulog import ULog
    except ImportError:
        raise StudyError("pyulog is not installed (use the Python of gcs-scripts/requirements.txt)") from None
    try:
        log = ULog(str(path), message_name_filter_list=list(topics))
    except Exception as exc:  # pyulog raises bare exceptions on malformed files
        raise StudyError(f"{path}: cannot read the ULog: {exc}") from None
    data = {d.name: dict(d.data) for d in log.data_list if d.multi_id == 0}
    missing = [name for name in topics if name not in data]
    if missing:
        raise StudyError(f"{path}: topic(s) missing from the log: {', '.join(missing)}")
    for fields in data.values():
        fields["t"] = fields["timestamp"] * 1e-6
    return data


def vector(topic, field, n=3):
    """The array field[0..n) of a topic as an (N, n) array."""
    return np.column_stack([topic[f"{field}[{i}]"] for i in range(n)])


def settling_time(t, y, target, band=SETTLING_BAND):
    """First time after which |y − target| ≤ band·|target| for the rest of the log [s]; None if the last
    sample is outside."""
    outside = np.abs(y - target) > band * abs(target)
    if outside[-1]:
        return None
    last = np.flatnonzero(outside)
    return float(t[0] if last.size == 0 else t[last[-1] + 1])


def load_estimate(path):
    """The estimator's per-sample CSV as {column: array}."""
    try:
        with path.open(encoding="utf-8") as f:
            names = f.readline().strip().split(",")
            data = np.loadtxt(f, delimiter=",", ndmin=2)
    except (OSError, ValueError) as exc:
        raise StudyError(f"{path}: cannot read the estimate: {exc}") from None
    expected = ["t", *WRENCH, "mass"]
    if names != expected or data.shape[0] == 0 or data.shape[1] != len(names):
        raise StudyError(f"{path}: expected the columns {','.join(expected)} and at least one row")
    return {name: data[:, i] for i, name in enumerate(names)}


def study_ex4(binary, out):
    """Exercise 4: one flight, six estimator designs; returns the report written to ex4_tests.json."""
    flight = out / "ex4" / "flight"
    summary = fly(binary, EX4_SCENARIO, flight)
    log = flight / "run.ulg"
    truth_topic = read_topics(log, ["external_wrench_truth"])["external_wrench_truth"]
    force = vector(truth_topic, "force")
    force[:, 2] += truth_topic["mass_mismatch_force"]
    truth = {"t": truth_topic["t"], "force": force, "torque": vector(truth_topic, "torque"),
             "mass": truth_topic["mass"]}
    believed_mass = summary.get("believed_mass_kg")
    if not isinstance(believed_mass, (int, float)):
        raise StudyError(f"{flight / 'summary.json'}: no believed_mass_kg")
    _, airframe = scenario_airframe(EX4_SCENARIO)
    inertia = believed_inertia(airframe, EX4_SCENARIO)
    estimates_dir = out / "ex4" / "estimates"
    try:
        estimates_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise StudyError(f"{estimates_dir}: cannot create: {exc}") from None
    fx_true = float(force[-1, 0])
    tests, series = [], []
    for number, order, ripple, wp, note in DESIGNS:
        csv_path = estimates_dir / f"test{number}.csv"
        progress(f"ex4 test {number}: estimate, order {order}, {ripple:g} dB, Wp {wp:g} rad/s")
        result = parse_json(run_binary(binary, "estimate", "--log", log, "--mass", believed_mass,
                                       "--inertia", ",".join(map(repr, inertia)), "--order", order,
                                       "--ripple-db", ripple, "--wp", wp, "--out", csv_path),
                            f"rotorpilot estimate (test {number})")
        est = load_estimate(csv_path)
        settle = settling_time(est["t"], est["fx"], fx_true)
        tests.append({
            "test": number, "order": order, "ripple_db": ripple, "wp_rad_s": wp, "note": note,
            "samples": result.get("samples"), "final": result.get("final"),
            "mass_estimate_kg": result.get("mass_estimate"),
            "settling_time_s": settle,
            "settling": "does not settle" if settle is None else f"{settle:.3f} s",
            "estimate_csv": str(csv_path.relative_to(out)),
        })
        series.append(est)
    report = {
        "scenario": EX4_SCENARIO.name, "log": str(log.relative_to(out)), "believed_mass_kg": believed_mass,
        "inertia_kg_m2": inertia, "settling_band": SETTLING_BAND,
        "settling_signal": f"fx, |fx − {fx_true:g}| ≤ {SETTLING_BAND * abs(fx_true):g} N",
        "truth": {"force_n": force[-1].tolist(), "torque_n_m": truth["torque"][-1].tolist(),
                  "mass_kg": float(truth["mass"][-1])},
        "tests": tests,
    }
    with plot_run.matplotlib_agg():
        for name, kind in (("ex4_forces.png", "force"), ("ex4_torques.png", "torque")):
            save(homework_figures.ex4_wrench(tests, series, truth, kind), out / name)
    write_json(out / "ex4_tests.json", report)
    print(format_ex4(report))
    return report


def format_ex4(report):
    """The Ex. 4 table as text."""
    head = (f"{'test':>4} {'r':>3} {'ripple':>7} {'Wp':>6}  " + " ".join(f"{k:>9}" for k in WRENCH)
            + f" {'mass':>8}  settling f̂x (2 %)")
    units = f"{'':>4} {'':>3} {'[dB]':>7} {'[rad/s]':>6}  " + " ".join(
        f"{'[N]' if k[0] == 'f' else '[N·m]':>9}" for k in WRENCH) + f" {'[kg]':>8}"
    lines = ["Exercise 4: wrench estimator designs over one flight", head, units]
    for test in report["tests"]:
        final = test["final"] or {}
        values = " ".join(f"{final.get(k, float('nan')):>9.5f}" for k in WRENCH)
        lines.append(f"{test['test']:>4} {test['order']:>3} {test['ripple_db']:>7g} {test['wp_rad_s']:>6g}  "
                     f"{values} {test['mass_estimate_kg']:>8.5f}  {test['settling']}")
    truth = report["truth"]
    lines.append("truth: force " + ", ".join(f"{v:g}" for v in truth["force_n"]) + " N, torque "
                 + ", ".join(f"{v:g}" for v in truth["torque_n_m"]) + f" N·m, mass {truth['mass_kg']:g} kg")
    return "\n".join(lines)


def rotor_hubs(binary, airframe_name):
    """Rotor hubs in the body FRD frame [m] and spins (+1 counter-clockwise seen from above) from the
    allocation matrix: a rotor at (x, y) with thrust T along −z gives τx = −y T and τy = x T."""
    alloc = parse_json(run_binary(binary, "alloc", "--airframe", airframe_name, "--json"), "rotorpilot alloc")
    try:
        g = np.asarray(alloc["G"], dtype=np.float64)
        thrust = g[0]
        hubs = np.column_stack([g[2] / thrust, -g[1] / thrust, np.zeros_like(thrust)])
    except (KeyError, ValueError, IndexError) as exc:
        raise StudyError(f"rotorpilot alloc --airframe {airframe_name}: unexpected output: {exc}") from None
    return hubs, np.sign(g[3])


def study_ex5(binary, out):
    """Exercise 5: one flight of the geometric controller; returns the report written to ex5_summary.json."""
    flight = out / "ex5" / "flight"
    summary = fly(binary, EX5_SCENARIO, flight)
    log = flight / "run.ulg"
    topics = read_topics(log, ["controller_errors", "allocation_status", "vehicle_local_position",
                               "vehicle_attitude", "vehicle_local_position_setpoint"])
    trajectory = read_toml(EX5_SCENARIO).get("trajectory", {})
    goal, t_end = trajectory.get("goal"), trajectory.get("duration")
    if not (isinstance(goal, list) and len(goal) == 3):
        raise StudyError(f"{EX5_SCENARIO}: [trajectory] has no goal [x, y, z]")
    mass, weight = summary.get("true_mass_kg"), summary.get("true_weight_n")
    if not (isinstance(mass, (int, float)) and isinstance(weight, (int, float))):
        raise StudyError(f"{flight / 'summary.json'}: no true_mass_kg / true_weight_n")
    errors = topics["controller_errors"]
    alloc = topics["allocation_status"]
    pos = topics["vehicle_local_position"]
    p = np.column_stack([pos["x"], pos["y"], pos["z"]])
    q = vector(topics["vehicle_attitude"], "q", 4)
    airframe_name, airframe = scenario_airframe(EX5_SCENARIO)
    hubs, spins = rotor_hubs(binary, airframe_name)
    groups = {name: vector(errors, name) for name in ("e_p", "e_v", "e_r", "e_omega")}
    # The summary's final position and thrust are the simulator's (f64); the log's are rounded to f32.
    final_p = np.asarray(summary.get("final_position_m", p[-1]), dtype=np.float64)
    final_error = final_p - np.asarray(goal, dtype=np.float64)
    thrust = float(summary.get("final_thrust_n", alloc["thrust"][-1]))
    report = {
        "scenario": EX5_SCENARIO.name, "log": str(log.relative_to(out)), "duration_s": float(errors["t"][-1]),
        "goal_m": goal, "final_position_m": final_p.tolist(),
        "final_position_error_m": final_error.tolist(),
        "final_position_error_norm_m": float(np.linalg.norm(final_error)),
        "final_thrust_n": thrust, "mass_kg": mass, "weight_n": weight,
        "final_thrust_over_weight": thrust / weight,
        "final_torque_n_m": vector(alloc, "torque")[-1].tolist(),
        "max_abs_errors": {name: np.abs(v).max(axis=0).tolist() for name, v in groups.items()},
        "max_error_norms": {name: float(np.linalg.norm(v, axis=1).max()) for name, v in groups.items()},
        "final_error_norms": {name: float(np.linalg.norm(v[-1])) for name, v in groups.items()},
    }
    setpoint = topics["vehicle_local_position_setpoint"]
    reference = np.column_stack([setpoint["x"], setpoint["y"], setpoint["z"]])
    rotor_radius = airframe.get("rotors", {}).get("radius")
    progress("ex5: drawing the figures")
    with plot_run.matplotlib_agg():
        for name, fig in homework_figures.ex5_figures(errors, alloc, weight, t_end):
            save(fig, out / name)
        save(homework_figures.ex5_final_configuration(p, reference, q[-1], goal, hubs, spins, rotor_radius,
                                                      report["final_position_error_norm_m"]),
             out / "ex5_final_configuration.png")
    write_json(out / "ex5_summary.json", report)
    print(format_ex5(report))
    return report


def format_ex5(report):
    """The Ex. 5 summary as text."""
    err = report["final_position_error_m"]
    return "\n".join([
        "Exercise 5: geometric controller, quintic to the goal and hover",
        f"final position error {report['final_position_error_norm_m']:.3e} m "
        f"({', '.join(f'{v:.2e}' for v in err)})",
        f"final thrust {report['final_thrust_n']:.6f} N, m g = {report['weight_n']:.6f} N "
        f"(ratio {report['final_thrust_over_weight']:.6f})",
        "largest |e_p| {:.4f} m, |e_v| {:.4f} m/s, |e_R| {:.5f}, |e_ω| {:.5f} rad/s".format(
            *(report["max_error_norms"][k] for k in ("e_p", "e_v", "e_r", "e_omega"))),
    ])


def save(fig, path):
    """Writes a figure as PNG; StudyError if it cannot."""
    try:
        fig.savefig(path, dpi=DPI)
    except OSError as exc:
        raise StudyError(f"{path}: cannot write: {exc}") from None
    progress(f"wrote {path}")


def write_json(path, value):
    """Writes value as indented JSON; StudyError if it cannot."""
    try:
        path.write_text(json.dumps(value, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    except OSError as exc:
        raise StudyError(f"{path}: cannot write: {exc}") from None
    progress(f"wrote {path}")


def main(argv=None):
    """Entry point: returns the exit status (0 ok, 2 error)."""
    args = parse_args(argv)
    try:
        binary = find_binary(args.binary)
        try:
            args.out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise StudyError(f"{args.out}: cannot create the output directory: {exc}") from None
        if args.only in (None, "ex4"):
            study_ex4(binary, args.out)
        if args.only in (None, "ex5"):
            study_ex5(binary, args.out)
    except StudyError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
