"""`rotorpilot sim` end to end: the shipped homework scenario writes run.ulg, summary.json and, with
`--csv`, run.csv."""
import csv
import json
import pathlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_ex5_writes_every_signal_and_reaches_the_goal(rotorpilot, tmp_path):
    out = tmp_path / "ex5"
    proc = rotorpilot("sim", str(ROOT / "scenarios" / "ex5_geometric.toml"), "--out", str(out), "--csv")
    assert proc.returncode == 0, proc.stderr
    printed = json.loads(proc.stdout)
    summary = json.loads((out / "summary.json").read_text())
    assert summary == printed
    assert summary["exit"] == "complete" and summary["controller"] == "geometric"
    assert summary["final_position_error_norm_m"] < 0.01
    assert abs(summary["final_thrust_n"] - 1.5 * 9.81) < 1e-3 * 1.5 * 9.81

    with open(out / "run.csv", newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    for column in ["t", "x_ref", "ex", "evz", "roll_ref", "eR_x", "ew_z", "thrust", "tau_z", "omega_4",
                   "fx_hat", "tz_true", "mass_hat", "saturated"]:
        assert column in header, column
    assert len(rows) == 15000
    data = {name: [row[i] for row in rows] for i, name in enumerate(header)}
    t = np.array(data["t"], dtype=float)
    assert np.all(np.diff(t) > 0) and abs(t[-1] - 14.999) < 1e-9
    # Estimator off: its columns are empty; the truth columns are zero (no disturbance).
    assert set(data["fx_hat"]) == {""}
    assert np.all(np.array(data["fx_true"], dtype=float) == 0.0)
    # The reference ends at the goal and the position follows it.
    assert [float(data[k][-1]) for k in ("x_ref", "y_ref", "z_ref")] == [1.0, 1.0, -1.0]
    err = np.abs(np.array(data["x"], dtype=float) - np.array(data["x_ref"], dtype=float))
    assert err.max() < 0.01


def test_estimator_scenario_logs_estimate_and_truth(rotorpilot, tmp_path):
    out = tmp_path / "ex4"
    proc = rotorpilot("sim", str(ROOT / "scenarios" / "ex4_estimator.toml"), "--out", str(out), "--csv")
    assert proc.returncode == 0, proc.stderr
    with open(out / "run.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]
    assert abs(float(last["fx_hat"]) - 0.5) < 0.005 and float(last["fx_true"]) == 0.5
    assert abs(float(last["tz_hat"]) - 0.2) < 0.002 and float(last["tz_true"]) == 0.2
    assert abs(float(last["mass_hat"]) - 1.7) < 0.0085


def test_bad_scenario_names_the_field(rotorpilot, tmp_path):
    text = (ROOT / "scenarios" / "ex5_geometric.toml").read_text().replace('kind = "geometric"', 'kind = "lqr"')
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    proc = rotorpilot("sim", str(bad), "--out", str(tmp_path / "out"))
    assert proc.returncode != 0
    assert "bad.toml" in proc.stderr and "lqr" in proc.stderr
    assert not (tmp_path / "out" / "summary.json").exists()


def test_plot_run_renders_a_real_run(rotorpilot, tmp_path):
    import subprocess
    import sys

    out = tmp_path / "ex4"
    scenario = (ROOT / "scenarios" / "ex4_estimator.toml").read_text().replace("duration = 40.0", "duration = 3.0")
    (tmp_path / "short.toml").write_text(scenario)
    assert rotorpilot("sim", str(tmp_path / "short.toml"), "--out", str(out), "--csv").returncode == 0
    proc = subprocess.run([sys.executable, str(ROOT / "gcs-scripts" / "plot_run.py"), str(out)],
                          capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    for name in ["position", "errors", "attitude", "inputs", "rotors", "wrench", "mass"]:
        png = out / f"{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000, name
