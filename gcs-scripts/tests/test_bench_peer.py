"""bench_peer.py: RotorPy and rotorpilot fly the same circle; the printed figures are consistent.

No timing thresholds: the machine is shared, so the speed ratio is reported, never asserted.
"""
import json
import math
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest
from script_module import load_script

SCRIPT = pathlib.Path(__file__).resolve().parents[1] / "bench_peer.py"
# Short flight: 1.5 s, of which 0.5 s spinning up from hover, on a 1 m circle at 1 m/s.
TASK = ["--duration", "1.5", "--ramp", "0.5", "--radius", "1", "--speed", "1"]
DURATION_S, RAMP_S, RADIUS_M, SPEED_M_S, ALTITUDE_M = 1.5, 0.5, 1.0, 1.0, 2.0
NAMES = ("RotorPy (SE3Control)", "rotorpilot", "rotorpilot + run.ulg")
ROW_FIELDS = {"simulator", "step_s", "steps", "sim_time_s", "wall_s", "steps_per_wall_s", "sim_s_per_wall_s",
              "final_error_m", "rms_error_m", "final_position_ned_m", "final_reference_ned_m"}


def run_script(*args, env=None):
    """Runs bench_peer.py with this Python; returns the CompletedProcess."""
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=120,
                          check=False, env=env)


def reference_ned(t_s):
    """The task's reference position at t_s (after the ramp), NED [m]."""
    theta = SPEED_M_S / RADIUS_M * (t_s - 0.5 * RAMP_S)
    return np.array([RADIUS_M * math.cos(theta), RADIUS_M * math.sin(theta), -ALTITUDE_M])


@pytest.fixture(scope="module")
def report(rotorpilot_bin):
    """The --json report of one short run at RotorPy's 1 kHz default."""
    proc = run_script(*TASK, "--rotorpilot", str(rotorpilot_bin), "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def rows_by_name(report):
    """The simulator rows keyed by name."""
    return {row["simulator"]: row for row in report["simulators"]}


def test_json_fields(report):
    assert set(report) >= {"task", "machine", "rotorpy_version", "repeat", "simulators", "comparison"}
    assert report["task"]["airframe"] == "quad_x" and report["task"]["mass_kg"] == 1.5
    assert report["task"]["period_s"] == pytest.approx(2 * math.pi * RADIUS_M / SPEED_M_S)
    assert report["machine"]["cores"] >= 1 and report["machine"]["cpu"]
    assert report["rotorpy_version"] == "3.0.0"
    rows = rows_by_name(report)
    assert tuple(rows) == NAMES
    for row in rows.values():
        assert set(row) == ROW_FIELDS
    assert set(report["comparison"]) == {"ratio_steps_per_wall_s", "ratio_steps_per_wall_s_with_log",
                                         "ratio_sim_s_per_wall_s", "target_ratio", "target_met"}


def test_step_counts_match_duration_and_rate(report):
    for row in report["simulators"]:
        assert row["step_s"] == pytest.approx(0.001)
        assert row["steps"] == round(DURATION_S / row["step_s"]) == 1500
        assert row["sim_time_s"] == pytest.approx(DURATION_S)


def test_rates_and_ratios_follow_from_the_figures(report):
    for row in report["simulators"]:
        assert row["wall_s"] > 0
        assert row["steps_per_wall_s"] == pytest.approx(row["steps"] / row["wall_s"], rel=1e-12)
        assert row["sim_s_per_wall_s"] == pytest.approx(row["sim_time_s"] / row["wall_s"], rel=1e-12)
    rows, cmp_ = rows_by_name(report), report["comparison"]
    rotorpy = rows["RotorPy (SE3Control)"]["steps_per_wall_s"]
    assert cmp_["ratio_steps_per_wall_s"] == pytest.approx(rows["rotorpilot"]["steps_per_wall_s"] / rotorpy)
    assert cmp_["ratio_steps_per_wall_s_with_log"] == pytest.approx(
        rows["rotorpilot + run.ulg"]["steps_per_wall_s"] / rotorpy)
    assert cmp_["ratio_sim_s_per_wall_s"] == pytest.approx(
        rows["rotorpilot"]["sim_s_per_wall_s"] / rows["RotorPy (SE3Control)"]["sim_s_per_wall_s"])
    assert cmp_["target_ratio"] == 1000
    assert cmp_["target_met"] == (cmp_["ratio_steps_per_wall_s"] >= 1000)


def test_both_flew_the_circle(report):
    rows = rows_by_name(report)
    # The last recorded sample: rotorpilot's last tick starts at t = T - dt, RotorPy's state is at T.
    ends = {"RotorPy (SE3Control)": DURATION_S, "rotorpilot": DURATION_S - 0.001,
            "rotorpilot + run.ulg": DURATION_S - 0.001}
    start = np.array([RADIUS_M, 0.0, -ALTITUDE_M])
    for name, row in rows.items():
        reference = np.array(row["final_reference_ned_m"])
        position = np.array(row["final_position_ned_m"])
        assert reference == pytest.approx(reference_ned(ends[name]), abs=1e-9), name
        assert np.linalg.norm(reference - start) > 1.0, name  # 1.25 rad round the circle
        assert np.linalg.norm(position - reference) == pytest.approx(row["final_error_m"], abs=1e-9), name
        assert row["final_error_m"] < 0.15, name
        assert row["rms_error_m"] < 0.1, name
    assert rows["rotorpilot"]["rms_error_m"] < 0.02
    assert rows["rotorpilot + run.ulg"]["final_error_m"] == rows["rotorpilot"]["final_error_m"]


def parse_table(text):
    """{simulator: [step ms, steps, wall s, steps/s, sim s/wall s, final err, RMS err]} and the ratios."""
    rows = {}
    for name in NAMES:
        line = next(ln for ln in text.splitlines() if ln.startswith(name + " ") and "steps/s" not in ln)
        rows[name] = [float(v) for v in line[len(name):].split()]
    ratio = float(re.search(r"steps per wall second: ([0-9.]+)x", text).group(1))
    ratio_log = float(re.search(r"run\.ulg every tick: ([0-9.]+)x", text).group(1))
    ratio_sim = float(re.search(r"simulated seconds per wall second: ([0-9.]+)x", text).group(1))
    return rows, ratio, ratio_log, ratio_sim


def test_text_ratio_from_printed_figures_at_100_hz(rotorpilot_bin):
    proc = run_script(*TASK, "--rotorpy-rate", "100", "--rotorpilot", str(rotorpilot_bin))
    assert proc.returncode == 0, proc.stderr
    rows, ratio, ratio_log, ratio_sim = parse_table(proc.stdout)
    rotorpy, rotorpilot, with_log = (rows[name] for name in NAMES)
    assert rotorpy[:2] == [10.0, 150.0]
    assert rotorpilot[:2] == with_log[:2] == [1.0, 1500.0]
    assert ratio == pytest.approx(rotorpilot[3] / rotorpy[3], rel=2e-3)
    assert ratio_log == pytest.approx(with_log[3] / rotorpy[3], rel=2e-3)
    assert ratio_sim == pytest.approx(rotorpilot[4] / rotorpy[4], rel=2e-3)
    assert ratio_sim == pytest.approx(ratio / 10, rel=1e-3)  # RotorPy's step is 10x rotorpilot's
    assert ("target >= 1000x: met" in proc.stdout) == (ratio >= 1000)
    assert rotorpy[5] < 0.15 and rotorpy[6] < 0.1


def test_circle_derivatives_are_consistent():
    bench = load_script("bench_peer")
    task = bench.Task(DURATION_S, RADIUS_M, SPEED_M_S, RAMP_S)
    h = 1e-5
    chain = ("x", "x_dot", "x_ddot", "x_dddot", "x_ddddot")
    for t in (0.1, 0.3, 0.45, 1.0):
        before, at, after = (bench.circle_flat_outputs(task, t + d) for d in (-h, 0.0, h))
        for lower, higher in zip(chain, chain[1:]):
            numeric = (after[lower] - before[lower]) / (2 * h)
            assert numeric == pytest.approx(at[higher], abs=1e-4), (t, higher)
        assert np.linalg.norm(at["x"][:2]) == pytest.approx(RADIUS_M)
    assert np.linalg.norm(bench.circle_flat_outputs(task, 1.0)["x_dot"]) == pytest.approx(SPEED_M_S)


def test_help():
    proc = run_script("--help")
    assert proc.returncode == 0
    for option in ("--duration", "--radius", "--speed", "--rotorpilot", "--json"):
        assert option in proc.stdout


def test_missing_binary_is_an_error(tmp_path):
    proc = run_script("--rotorpilot", str(tmp_path / "no-such-rotorpilot"), "--duration", "0.1")
    assert proc.returncode == 1
    assert proc.stderr.startswith("error: rotorpilot binary not found")
    assert "Traceback" not in proc.stderr


def test_rotorpy_not_installed_is_an_error(tmp_path, rotorpilot_bin):
    shadow = tmp_path / "rotorpy"
    shadow.mkdir()
    (shadow / "__init__.py").write_text("raise ImportError('No module named rotorpy')\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    proc = run_script("--rotorpilot", str(rotorpilot_bin), "--duration", "0.1", env=env)
    assert proc.returncode == 1
    assert proc.stderr.startswith("error: RotorPy is not installed")
    assert "Traceback" not in proc.stderr


def test_bad_arguments_exit_2():
    proc = run_script("--duration", "0")
    assert proc.returncode == 2
    assert "must be > 0" in proc.stderr
