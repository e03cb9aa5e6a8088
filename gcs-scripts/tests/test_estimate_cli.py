"""`rotorpilot estimate`: the offline estimator of homework exercise 4 over a CSV log, a run.csv or
a ULog file."""
import csv
import json

import numpy as np
import pytest

G = 9.81
COLUMNS = ["t", "thrust", "tau_x", "tau_y", "tau_z", "vx", "vy", "vz", "phi", "theta", "psi",
           "phi_dot", "theta_dot", "psi_dot"]
ARGS = ["--mass", "1.5", "--inertia", "1.2416,1.2416,2.4832", "--order", "1", "--ripple-db", "3", "--wp", "2"]


def write_log(path, seconds=20.0, thrust=1.7 * G, yaw_torque=0.2, columns=COLUMNS):
    """A vehicle held level and still by a thrust equal to its true weight (1.7 kg) while an
    external yaw torque spins it up (I_z = 2.4832 kg·m²)."""
    t = np.arange(int(round(seconds / 1e-3))) * 1e-3
    data = {name: np.zeros_like(t) for name in COLUMNS}
    data["t"] = t
    data["thrust"] = np.full_like(t, thrust)
    data["psi_dot"] = yaw_torque / 2.4832 * t
    data["psi"] = 0.5 * yaw_torque / 2.4832 * t ** 2
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for row in zip(*(data[c] for c in columns)):
            w.writerow([repr(float(x)) for x in row])
    return len(t)


def test_mass_and_yaw_torque_are_recovered(rotorpilot, tmp_path):
    log, out = tmp_path / "log.csv", tmp_path / "out.csv"
    n = write_log(log)
    proc = rotorpilot("estimate", "--log", str(log), *ARGS, "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout)
    assert result["samples"] == n
    assert result["mass_estimate"] == pytest.approx(1.7, rel=0.005)
    assert result["final"]["fz"] == pytest.approx(0.2 * G, rel=0.01)
    assert result["final"]["tz"] == pytest.approx(0.2, rel=0.01)
    assert abs(result["final"]["fx"]) < 1e-9 and abs(result["final"]["tx"]) < 1e-9
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t", "fx", "fy", "fz", "tx", "ty", "tz", "mass"]
    assert len(rows) == n + 1
    last = [float(x) for x in rows[-1]]
    assert last[1:7] == pytest.approx([result["final"][k] for k in ("fx", "fy", "fz", "tx", "ty", "tz")], rel=1e-12)
    assert last[7] == pytest.approx(result["mass_estimate"], rel=1e-12)


def test_columns_in_another_order_give_the_same_result(rotorpilot, tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    write_log(a, seconds=2.0)
    write_log(b, seconds=2.0, columns=list(reversed(COLUMNS)))
    ra = json.loads(rotorpilot("estimate", "--log", str(a), *ARGS).stdout)
    rb = json.loads(rotorpilot("estimate", "--log", str(b), *ARGS).stdout)
    assert ra == rb


@pytest.mark.parametrize("edit,expected", [
    (lambda lines: [lines[0].replace(",psi_dot", "")] + [row.rsplit(",", 1)[0] for row in lines[1:]],
     "column psi_dot: missing column"),
    (lambda lines: lines[:5] + [",".join("nan" if i == 7 else x for i, x in enumerate(lines[5].split(",")))]
     + lines[6:],
     "line 6, column vz: \"nan\" is not a finite number"),
    (lambda lines: lines[:5] + [lines[3]] + lines[6:], "line 6, column t: time"),
    (lambda lines: [lines[0]] + lines[1::2], "line 3, column t: sample time"),
    (lambda lines: lines[:1], "no data rows"),
])
def test_bad_logs_name_the_line_and_column(rotorpilot, tmp_path, edit, expected):
    log = tmp_path / "log.csv"
    write_log(log, seconds=0.02)
    lines = log.read_text().splitlines()
    log.write_text("\n".join(edit(lines)) + "\n")
    proc = rotorpilot("estimate", "--log", str(log), *ARGS)
    assert proc.returncode != 0
    assert expected in proc.stderr and "log.csv" in proc.stderr, proc.stderr


def test_bad_options_are_refused(rotorpilot, tmp_path):
    log = tmp_path / "log.csv"
    write_log(log, seconds=0.01)
    base = ["estimate", "--log", str(log), "--order", "1", "--ripple-db", "3", "--wp", "2"]
    bad_mass = rotorpilot(*base, "--mass", "-1", "--inertia", "1,1,1")
    assert bad_mass.returncode != 0 and "mass" in bad_mass.stderr
    bad_inertia = rotorpilot(*base, "--mass", "1.5", "--inertia", "1,1")
    assert bad_inertia.returncode != 0 and "--inertia" in bad_inertia.stderr
    unstable = rotorpilot("estimate", "--log", str(log), "--mass", "1.5", "--inertia", "1,1,1",
                          "--order", "13", "--ripple-db", "3", "--wp", "20")
    assert unstable.returncode != 0 and "largest stable passband edge" in unstable.stderr
    missing = rotorpilot("estimate", "--log", str(tmp_path / "nope.csv"), *ARGS)
    assert missing.returncode != 0 and "nope.csv" in missing.stderr


def test_the_homework_workflow_runs_on_the_logs_sim_writes(rotorpilot, tmp_path):
    """Ex. 4 end to end: fly the scenario, then run the offline estimator on its ULog and its
    run.csv as they are; both recover the disturbance and the mass."""
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    out = tmp_path / "ex4"
    proc = rotorpilot("sim", str(root / "scenarios" / "ex4_estimator.toml"), "--out", str(out), "--csv")
    assert proc.returncode == 0, proc.stderr
    for log in (out / "run.ulg", out / "run.csv"):
        proc = rotorpilot("estimate", "--log", str(log), *ARGS)
        assert proc.returncode == 0, proc.stderr
        result = json.loads(proc.stdout)
        assert result["samples"] == 40000, log
        final = result["final"]
        assert final["fx"] == pytest.approx(0.5, rel=0.01) and final["fy"] == pytest.approx(0.5, rel=0.01), log
        assert final["fz"] == pytest.approx(0.2 * G, rel=0.01) and final["tz"] == pytest.approx(0.2, rel=0.01), log
        assert result["mass_estimate"] == pytest.approx(1.7, rel=0.005), log


def test_a_log_without_every_tick_is_refused_with_the_reason(rotorpilot, tmp_path):
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    flight = tmp_path / "fly.ulg"
    assert rotorpilot("fly", "--duration", "1", "--log", str(flight)).returncode == 0
    proc = rotorpilot("estimate", "--log", str(flight), *ARGS)
    assert proc.returncode == 0 and json.loads(proc.stdout)["samples"] == 1000, "fly --log has every tick"
    data = flight.read_bytes()
    broken = tmp_path / "broken.ulg"
    broken.write_bytes(data[:16] + b"\xff" * 64)
    proc = rotorpilot("estimate", "--log", str(broken), *ARGS)
    assert proc.returncode != 0 and str(broken) in proc.stderr
    assert "panicked" not in proc.stderr
    sparse = tmp_path / "sparse"
    scenario = (root / "scenarios" / "ex4_estimator.toml").read_text().replace("duration = 40.0", "duration = 1.0")
    (tmp_path / "short.toml").write_text(scenario)
    assert rotorpilot("sim", str(tmp_path / "short.toml"), "--out", str(sparse)).returncode == 0
    proc = rotorpilot("estimate", "--log", str(sparse / "run.ulg"), *ARGS, "--ts", "0.002")
    assert proc.returncode != 0 and "differs from the expected 0.002 s" in proc.stderr, proc.stderr
    assert "every tick" in proc.stderr and str(sparse / "run.ulg") in proc.stderr
