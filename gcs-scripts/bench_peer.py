#!/usr/bin/env python3
"""Fly the same hover-and-circle task in RotorPy and in rotorpilot and compare their speed.

Usage:
    python gcs-scripts/bench_peer.py [--duration S] [--radius M] [--speed M/S] [--ramp S]
                                     [--rotorpy-rate HZ] [--repeat N] [--rotorpilot PATH] [--json]

The task: the vehicle starts hovering at rest 2 m up at the circle's start point (due north of
the centre), then its angular rate ramps up from rest over ``--ramp`` s (minimum-jerk law, so
velocity and acceleration stay continuous) to ``--speed`` m/s on a horizontal circle of
``--radius`` m, turning north -> east, heading fixed north, no wind, until ``--duration`` s of
simulated time. Both simulators fly the same vehicle, rotorpilot's ``quad_x`` airframe (iris-like
1.5 kg X quad): RotorPy gets its mass, inertia, arm, thrust and torque coefficients, motor speed
limits and spin-up time constant as a ``quad_params`` dict, without aerodynamic drag (quad_x has
none).

- RotorPy (PyPI package ``rotorpy``): its ``Environment`` with ``Multirotor`` dynamics (scipy
  RK45 per step), its ``SE3Control`` geometric controller on the true state, default IMU and
  motion-capture models and the null estimator, stepping at ``--rotorpy-rate`` Hz (default
  1000 Hz, rotorpilot's step). Timed: ``Environment.run`` (its loop, which keeps every step in
  memory, and the arrays it builds at the end).
- rotorpilot: ``rotorpilot sim SCENARIO.toml`` (geometric controller, RK4 plant, motor lag) at its
  1 ms step, run twice: printing only its summary, and with ``--out DIR`` writing ``run.ulg`` (ULog, every tick)
  every tick and ``summary.json``. Timed: the loop, as ``wall_time_s`` in its summary.

Printed per simulator: step [ms], steps, wall seconds, steps per wall second, simulated seconds
per wall second, final and RMS position tracking error [m]; then the ratio of rotorpilot's steps
per wall second to RotorPy's (target: at least 1000x, reported, not enforced). With ``--repeat N``
each simulator flies N times and the median wall time counts. ``--json`` prints one JSON object
instead, which also holds each final position and its reference (NED [m]) and the machine.
Errors (a missing binary, RotorPy not installed, a run that stops early) print ``error: ...`` on
stderr and exit 1; bad arguments exit 2.
"""
import argparse
import json
import math
import os
import pathlib
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from importlib.metadata import version

import numpy as np

from rotorpilot_gcs import find_binary
from rotorpilot_gcs.process import checkout_binary

ROOT = pathlib.Path(__file__).resolve().parents[1]
ALTITUDE_M = 2.0
ROTORPILOT_STEP_S = 0.001
TARGET_RATIO = 1000.0

# rotorpilot's airframes/quad_x.toml, as RotorPy parameters.
QUAD_X = {
    "mass_kg": 1.5,
    "inertia_kg_m2": (0.029125, 0.029125, 0.055225),
    "arm_m": 0.25,
    "c_t": 5.84e-6,  # [N/(rad/s)^2]
    "c_q": 3.504e-7,  # [N*m/(rad/s)^2]
    "omega_max_rad_s": 1100.0,
    "tau_up_s": 0.0125,
}
GRAVITY_M_S2 = 9.81  # RotorPy's value


class BenchError(Exception):
    """A problem that ends the benchmark with exit status 1."""


class Task:
    """The hover-and-circle flight both simulators fly."""

    def __init__(self, duration_s, radius_m, speed_m_s, ramp_s):
        """Duration [s], circle radius [m], full speed [m/s], spin-up time from hover [s]."""
        self.duration_s = duration_s
        self.radius_m = radius_m
        self.speed_m_s = speed_m_s
        self.ramp_s = ramp_s

    @property
    def period_s(self):
        """Time per lap at full speed [s]."""
        return 2.0 * math.pi * self.radius_m / self.speed_m_s

    @property
    def omega_rad_s(self):
        """Full angular rate about the centre [rad/s]."""
        return self.speed_m_s / self.radius_m

    def as_dict(self):
        """The task's figures, units in the keys."""
        return {"duration_s": self.duration_s, "radius_m": self.radius_m, "speed_m_s": self.speed_m_s,
                "ramp_s": self.ramp_s, "period_s": self.period_s, "altitude_m": ALTITUDE_M,
                "airframe": "quad_x", "mass_kg": QUAD_X["mass_kg"]}


def min_jerk(tau):
    """Minimum-jerk law s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 and its first three derivatives."""
    t2 = tau * tau
    return (t2 * tau * (10.0 - 15.0 * tau + 6.0 * t2), 30.0 * t2 * (1.0 - tau) ** 2,
            60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2), 60.0 - 360.0 * tau + 360.0 * t2)


def circle_angle(task, t_s):
    """Angle travelled about the centre and its first four time derivatives at t_s [s]
    [rad, rad/s, rad/s^2, rad/s^3, rad/s^4], as rotorpilot's circle trajectory (no laps)."""
    w, tr = task.omega_rad_s, task.ramp_s
    if t_s <= 0.0:
        return (0.0, 0.0, 0.0, 0.0, 0.0)
    if t_s < tr:
        tau = t_s / tr
        s, ds, dds, ddds = min_jerk(tau)
        integral = tau ** 4 * (2.5 - 3.0 * tau + tau * tau)
        return (w * tr * integral, w * s, w * ds / tr, w * dds / tr ** 2, w * ddds / tr ** 3)
    return (w * (t_s - 0.5 * tr), w, 0.0, 0.0, 0.0)


def circle_flat_outputs(task, t_s):
    """RotorPy's flat outputs of the task at t_s [s], world ENU (x east, y north, z up) [m, m/s,
    m/s^2, m/s^3, m/s^4]; heading north (yaw pi/2) [rad, rad/s, rad/s^2]."""
    th, th1, th2, th3, th4 = circle_angle(task, t_s)
    r = task.radius_m
    radial = np.array([math.sin(th), math.cos(th), 0.0])  # from the centre; north at th = 0
    along = np.array([math.cos(th), -math.sin(th), 0.0])  # d(radial)/d(th): north -> east
    centre = np.array([0.0, 0.0, ALTITUDE_M])
    jerk_along, jerk_radial = th3 - th1 ** 3, -3.0 * th1 * th2
    return {
        "x": centre + r * radial,
        "x_dot": r * th1 * along,
        "x_ddot": r * (th2 * along - th1 * th1 * radial),
        "x_dddot": r * (jerk_along * along + jerk_radial * radial),
        "x_ddddot": r * ((th4 - 6.0 * th1 * th1 * th2) * along
                         + (-4.0 * th1 * th3 - 3.0 * th2 * th2 + th1 ** 4) * radial),
        "yaw": math.pi / 2.0,
        "yaw_dot": 0.0,
        "yaw_ddot": 0.0,
    }


class RampedCircle:
    """RotorPy trajectory object (``update(t)`` -> flat outputs) for the task."""

    def __init__(self, task):
        """Keeps the task."""
        self.task = task

    def update(self, t):
        """Flat outputs at t [s]; see circle_flat_outputs."""
        return circle_flat_outputs(self.task, t)


def enu_to_ned(p):
    """A position world ENU [m] as NED [m]."""
    return [float(p[1]), float(p[0]), -float(p[2])]


def scenario_toml(task):
    """rotorpilot scenario text of the task (NED: 2 m up is z = -2)."""
    return "\n".join([
        'name = "bench_peer_circle"',
        f"duration = {task.duration_s!r}",
        f"dt = {ROTORPILOT_STEP_S!r}",
        "",
        "[airframe]",
        'preset = "quad_x"',
        "",
        "[initial]",
        f"position = [{task.radius_m!r}, 0.0, {-ALTITUDE_M!r}]",
        "",
        "[controller]",
        'kind = "geometric"',
        "",
        "[trajectory]",
        'kind = "circle"',
        f"centre = [0.0, 0.0, {-ALTITUDE_M!r}]",
        f"radius = {task.radius_m!r}",
        f"period = {task.period_s!r}",
        f"ramp = {task.ramp_s!r}",
        "",
    ])


def figures(name, step_s, steps, wall_s, errors_m, final_ned_m):
    """One simulator's row: step [s], steps, wall time [s], (final, RMS) position error [m] and
    (final position, its reference) NED [m], with the rates they give [steps/s, s/s]."""
    return {
        "simulator": name,
        "step_s": step_s,
        "steps": steps,
        "sim_time_s": steps * step_s,
        "wall_s": wall_s,
        "steps_per_wall_s": steps / wall_s,
        "sim_s_per_wall_s": steps * step_s / wall_s,
        "final_error_m": errors_m[0],
        "rms_error_m": errors_m[1],
        "final_position_ned_m": final_ned_m[0],
        "final_reference_ned_m": final_ned_m[1],
    }


def run_rotorpilot_once(binary, scenario, out_dir):
    """Runs `rotorpilot sim` (with `--out out_dir` unless None) and returns its summary dict."""
    cmd = [str(binary), "sim", str(scenario)] + (["--out", str(out_dir)] if out_dir else [])
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600, check=False)
    except OSError as exc:
        raise BenchError(f"cannot run {binary}: {exc}") from exc
    if proc.returncode != 0:
        raise BenchError(f"{' '.join(cmd)} exited with {proc.returncode}: {proc.stderr.strip()}")
    text = (pathlib.Path(out_dir) / "summary.json").read_text() if out_dir is not None else proc.stdout
    try:
        return json.loads(text)
    except ValueError as exc:
        raise BenchError(f"{' '.join(cmd)}: summary is not JSON: {exc}") from exc


def run_rotorpilot(binary, task, with_log, repeat):
    """Flies the task `repeat` times in rotorpilot; figures of the median loop wall time."""
    with tempfile.TemporaryDirectory(prefix="bench_peer_") as tmp:
        scenario = pathlib.Path(tmp) / "circle.toml"
        scenario.write_text(scenario_toml(task))
        out_dir = pathlib.Path(tmp) / "run" if with_log else None
        summaries = [run_rotorpilot_once(binary, scenario, out_dir) for _ in range(repeat)]
    last = summaries[-1]
    if last["exit"] != "complete":
        raise BenchError(f"rotorpilot stopped early: {last['exit']} after {last['sim_time_s']} s")
    rms = math.sqrt(sum(e * e for e in last["rms_position_error_m"]))
    name = "rotorpilot + run.ulg" if with_log else "rotorpilot"
    wall_s = statistics.median(s["wall_time_s"] for s in summaries)
    return figures(name, last["dt_s"], last["ticks"], wall_s, (last["final_position_error_norm_m"], rms),
                   (last["final_position_m"], last["final_reference_m"]))


def import_rotorpy():
    """RotorPy's modules (Environment, Multirotor, SE3Control) and version; BenchError if missing."""
    try:
        from rotorpy.controllers.quadrotor_control import SE3Control
        from rotorpy.environments import Environment
        from rotorpy.vehicles.multirotor import Multirotor
    except ImportError as exc:
        raise BenchError(f"RotorPy is not installed ({exc}): pip install -r gcs-scripts/requirements.txt") from exc
    return Environment, Multirotor, SE3Control, version("rotorpy")


def rotorpy_quad_params():
    """quad_x as RotorPy's quad_params: body x forward, y left, z up; X layout with rotor 1
    front left and the spins alternating; no aerodynamic terms."""
    d = QUAD_X["arm_m"] / math.sqrt(2.0)
    ixx, iyy, izz = QUAD_X["inertia_kg_m2"]
    return {
        "mass": QUAD_X["mass_kg"], "Ixx": ixx, "Iyy": iyy, "Izz": izz, "Ixy": 0.0, "Ixz": 0.0, "Iyz": 0.0,
        "num_rotors": 4,
        "rotor_pos": {"r1": d * np.array([1.0, 1.0, 0.0]), "r2": d * np.array([-1.0, 1.0, 0.0]),
                      "r3": d * np.array([-1.0, -1.0, 0.0]), "r4": d * np.array([1.0, -1.0, 0.0])},
        "rotor_directions": np.array([1, -1, 1, -1]),
        "rI": np.zeros(3),
        "c_Dx": 0.0, "c_Dy": 0.0, "c_Dz": 0.0, "k_d": 0.0, "k_z": 0.0, "k_h": 0.0, "k_flap": 0.0,
        "k_eta": QUAD_X["c_t"], "k_m": QUAD_X["c_q"],
        "tau_m": QUAD_X["tau_up_s"],
        "rotor_speed_min": 0.0, "rotor_speed_max": QUAD_X["omega_max_rad_s"],
        "motor_noise_std": 0.0,
    }


def rotorpy_initial_state(task):
    """Hovering at rest at the start point, nose north, rotors at hover speed [m, m/s, -, rad/s]."""
    hover_rad_s = math.sqrt(QUAD_X["mass_kg"] * GRAVITY_M_S2 / (4.0 * QUAD_X["c_t"]))
    return {"x": circle_flat_outputs(task, 0.0)["x"], "v": np.zeros(3),
            "q": np.array([0.0, 0.0, math.sin(math.pi / 4.0), math.cos(math.pi / 4.0)]),  # [i, j, k, w]
            "w": np.zeros(3), "wind": np.zeros(3), "rotor_speeds": np.full(4, hover_rad_s)}


def run_rotorpy_once(modules, task, rate_hz):
    """Flies the task once in RotorPy; returns (wall seconds of Environment.run, its result)."""
    environment, multirotor, se3_control, _ = modules
    params = rotorpy_quad_params()
    vehicle = multirotor(params, initial_state=rotorpy_initial_state(task), aero=False)
    env = environment(vehicle=vehicle, controller=se3_control(params), trajectory=RampedCircle(task),
                      sim_rate=rate_hz)
    step_s = 1.0 / rate_hz
    # Its loop stops once its summed time reaches t_final: half a step short gives exactly N steps.
    t_final = round(task.duration_s / step_s) * step_s - 0.5 * step_s
    start = time.perf_counter()
    result = env.run(t_final=t_final, terminate=False)
    return time.perf_counter() - start, result


def run_rotorpy(modules, task, rate_hz, repeat):
    """Flies the task `repeat` times in RotorPy; figures of the median wall time."""
    runs = [run_rotorpy_once(modules, task, rate_hz) for _ in range(repeat)]
    result = runs[-1][1]
    if result["exit"].name != "TIMEOUT":
        raise BenchError(f"RotorPy stopped early: {result['exit'].value} at t = {result['time'][-1]:.3f} s")
    errors = np.linalg.norm(result["state"]["x"] - result["flat"]["x"], axis=1)
    steps = len(result["time"]) - 1
    wall_s = statistics.median(wall for wall, _ in runs)
    return figures("RotorPy (SE3Control)", 1.0 / rate_hz, steps, wall_s,
                   (float(errors[-1]), float(np.sqrt(np.mean(errors ** 2)))),
                   (enu_to_ned(result["state"]["x"][-1]), enu_to_ned(result["flat"]["x"][-1])))


def machine():
    """CPU model, core count and Python version of this machine."""
    cpu = platform.machine()
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version()}


def compare(rotorpy, rotorpilot, rotorpilot_log):
    """Ratios rotorpilot / RotorPy of steps and of simulated seconds per wall second [-]."""
    ratio = rotorpilot["steps_per_wall_s"] / rotorpy["steps_per_wall_s"]
    return {
        "ratio_steps_per_wall_s": ratio,
        "ratio_steps_per_wall_s_with_log": rotorpilot_log["steps_per_wall_s"] / rotorpy["steps_per_wall_s"],
        "ratio_sim_s_per_wall_s": rotorpilot["sim_s_per_wall_s"] / rotorpy["sim_s_per_wall_s"],
        "target_ratio": TARGET_RATIO,
        "target_met": ratio >= TARGET_RATIO,
    }


def fixed(value, significant):
    """value in fixed point with at least `significant` significant digits (222.37, 1044763)."""
    digits = int(math.floor(math.log10(abs(value)))) + 1 if value else 1
    return f"{value:.{max(0, significant - digits)}f}"


def format_text(report):
    """The report as a table and the ratio lines."""
    task, mach = report["task"], report["machine"]
    lines = [
        f"task: hover 2 m up, ramp {task['ramp_s']:g} s into a circle of radius {task['radius_m']:g} m at "
        f"{task['speed_m_s']:g} m/s (lap {task['period_s']:.3f} s), {task['duration_s']:g} s simulated, "
        f"quad_x ({task['mass_kg']:g} kg) in both, no wind",
        f"machine: {mach['cpu']}, {mach['cores']} cores, Python {mach['python']}, rotorpy {report['rotorpy_version']}",
        "",
        f"{'simulator':<22}{'step ms':>8}{'steps':>9}{'wall s':>11}{'steps/s':>12}{'sim s/wall s':>14}"
        f"{'final err m':>13}{'RMS err m':>11}",
    ]
    for row in report["simulators"]:
        lines.append(f"{row['simulator']:<22}{row['step_s'] * 1e3:>8.3g}{row['steps']:>9d}{row['wall_s']:>11.4g}"
                     f"{fixed(row['steps_per_wall_s'], 5):>12}{fixed(row['sim_s_per_wall_s'], 5):>14}"
                     f"{row['final_error_m']:>13.3g}{row['rms_error_m']:>11.3g}")
    cmp_ = report["comparison"]
    verdict = "met" if cmp_["target_met"] else "NOT met"
    lines += [
        "",
        f"ratio rotorpilot / RotorPy, steps per wall second: {cmp_['ratio_steps_per_wall_s']:.1f}x "
        f"(target >= {cmp_['target_ratio']:g}x: {verdict})",
        f"ratio with rotorpilot writing run.ulg every tick: {cmp_['ratio_steps_per_wall_s_with_log']:.1f}x",
        f"ratio of simulated seconds per wall second: {cmp_['ratio_sim_s_per_wall_s']:.1f}x",
    ]
    return "\n".join(lines)


def positive(kind):
    """argparse type: a number of `kind` (int or float) greater than zero."""
    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        if not value > 0 or not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
        return value
    return parse


def parse_args(argv):
    """Parses the command line."""
    parser = argparse.ArgumentParser(
        description="Fly the same hover-and-circle task in RotorPy and rotorpilot; compare steps per wall second.")
    parser.add_argument("--duration", type=positive(float), default=10.0, help="simulated time [s] (default 10)")
    parser.add_argument("--radius", type=positive(float), default=2.0, help="circle radius [m] (default 2)")
    parser.add_argument("--speed", type=positive(float), default=2.0, help="speed on the circle [m/s] (default 2)")
    parser.add_argument("--ramp", type=positive(float), default=2.0,
                        help="spin-up time from hover to full speed [s] (default 2)")
    parser.add_argument("--rotorpy-rate", type=positive(int), default=1000,
                        help="RotorPy's simulation rate [Hz] (default 1000 as rotorpilot; RotorPy's own default: 100)")
    parser.add_argument("--repeat", type=positive(int), default=1,
                        help="flights per simulator; the median wall time counts (default 1)")
    parser.add_argument("--rotorpilot", type=pathlib.Path,
                        default=None,
                        help="rotorpilot binary (default: $ROTORPILOT_BIN, else target/release/rotorpilot, else PATH)")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    return parser.parse_args(argv)


def run(args):
    """Flies both simulators and returns the report dict; BenchError on failure."""
    try:
        args.rotorpilot = find_binary(args.rotorpilot, fallback=checkout_binary())
    except FileNotFoundError as exc:
        raise BenchError(f"{exc} (or pass --rotorpilot PATH)") from None
    modules = import_rotorpy()
    task = Task(args.duration, args.radius, args.speed, args.ramp)
    rotorpilot = run_rotorpilot(args.rotorpilot, task, with_log=False, repeat=args.repeat)
    rotorpilot_log = run_rotorpilot(args.rotorpilot, task, with_log=True, repeat=args.repeat)
    rotorpy = run_rotorpy(modules, task, args.rotorpy_rate, args.repeat)
    return {
        "task": task.as_dict(),
        "machine": machine(),
        "rotorpy_version": modules[3],
        "repeat": args.repeat,
        "simulators": [rotorpy, rotorpilot, rotorpilot_log],
        "comparison": compare(rotorpy, rotorpilot, rotorpilot_log),
    }


def main(argv=None):
    """Entry point: returns the exit status (0 ok, 1 error; argparse exits 2 on bad usage)."""
    args = parse_args(argv)
    try:
        report = run(args)
    except BenchError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    print(json.dumps(report) if args.json else format_text(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
