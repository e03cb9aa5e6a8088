"""homework_study.py: homework exercises 4 and 5 reproduced with the real binary, run once per module."""
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

SCRIPT = pathlib.Path(__file__).resolve().parents[1] / "homework_study.py"
G = 9.81
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
FIGURES = ("ex4_forces.png", "ex4_torques.png", "ex5_position_errors.png", "ex5_velocity_errors.png",
           "ex5_attitude_errors.png", "ex5_rate_errors.png", "ex5_thrust.png", "ex5_torques.png",
           "ex5_final_configuration.png")
DESIGNS = [(1, 3.0, 2.0), (1, 3.0, 20.0), (1, 20.0, 20.0), (7, 3.0, 2.0), (7, 1.0, 5.0), (13, 1.0, 5.0)]
WRENCH = ("fx", "fy", "fz", "tx", "ty", "tz")


def study(*args):
    """Runs homework_study.py with this interpreter."""
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          timeout=600, check=False)


@pytest.fixture(scope="module")
def result(rotorpilot_bin, tmp_path_factory):
    """(output directory, completed process) of one full study."""
    out = tmp_path_factory.mktemp("homework_study")
    proc = study("--out", out, "--binary", rotorpilot_bin)
    assert proc.returncode == 0, proc.stderr
    return out, proc


@pytest.fixture(scope="module")
def ex4(result):
    """ex4_tests.json."""
    return json.loads((result[0] / "ex4_tests.json").read_text(encoding="utf-8"))


def test_every_figure_is_a_real_image(result):
    out, _ = result
    for name in FIGURES:
        data = (out / name).read_bytes()
        assert data[:8] == PNG_MAGIC, f"{name} is not a PNG"
        assert len(data) > 10_000, f"{name} is only {len(data)} bytes"


def test_stderr_holds_only_progress_and_stdout_the_tables(result):
    _, proc = result
    lines = proc.stderr.splitlines()
    assert lines and all(line.startswith("homework_study: ") for line in lines), proc.stderr
    assert "Exercise 4" in proc.stdout and "Exercise 5" in proc.stdout
    assert len([line for line in proc.stdout.splitlines() if line.split()[:1] in (["1"], ["6"])]) == 2


def test_six_designs_in_the_homework_order(ex4):
    assert [(t["order"], t["ripple_db"], t["wp_rad_s"]) for t in ex4["tests"]] == DESIGNS
    assert [t["test"] for t in ex4["tests"]] == [1, 2, 3, 4, 5, 6]
    assert ex4["truth"]["force_n"] == pytest.approx([0.5, 0.5, (1.7 - 1.5) * G], rel=1e-6)
    assert ex4["truth"]["torque_n_m"] == pytest.approx([0.0, 0.0, 0.2], abs=1e-6)


@pytest.mark.parametrize("index", [0, 1, 2])
def test_first_order_designs_recover_the_wrench_and_the_mass(ex4, index):
    test = ex4["tests"][index]
    final = test["final"]
    assert final["fx"] == pytest.approx(0.5, rel=0.01)
    assert final["fy"] == pytest.approx(0.5, rel=0.01)
    assert final["fz"] == pytest.approx((1.7 - 1.5) * G, rel=0.01)
    assert final["tz"] == pytest.approx(0.2, rel=0.01)
    assert abs(final["tx"]) < 0.002 and abs(final["ty"]) < 0.002
    assert test["mass_estimate_kg"] == pytest.approx(1.7, rel=0.005)
    assert test["mass_estimate_kg"] == pytest.approx(1.5 + final["fz"] / G, rel=1e-9)
    assert test["settling_time_s"] is not None


def test_ten_times_the_bandwidth_settles_faster(ex4):
    slow, fast = ex4["tests"][0]["settling_time_s"], ex4["tests"][1]["settling_time_s"]
    assert fast < slow, (fast, slow)


def settling(t, fx, target=0.5, band=0.02):
    """When |fx − target| last leaves the band, recomputed here from the estimator's CSV."""
    outside = np.abs(fx - target) > band * target
    if outside[-1]:
        return None
    last = np.flatnonzero(outside)
    return float(t[0] if last.size == 0 else t[last[-1] + 1])


def test_every_settling_time_is_the_estimate_csvs(result, ex4):
    out, _ = result
    for test in ex4["tests"]:
        data = np.loadtxt(out / test["estimate_csv"], delimiter=",", skiprows=1, ndmin=2)
        expected = settling(data[:, 0], data[:, 1])
        assert test["settling_time_s"] == expected
        assert test["settling"] == ("does not settle" if expected is None else f"{expected:.3f} s")
        assert [test["final"][k] for k in WRENCH] == pytest.approx(data[-1, 1:7], rel=1e-12, abs=1e-15)


def test_order_13_is_reported_as_the_estimator_writes_it(result, ex4, rotorpilot):
    out, _ = result
    proc = rotorpilot("estimate", "--log", str(out / ex4["log"]), "--mass", "1.5",
                      "--inertia", "1.2416,1.2416,2.4832", "--order", "13", "--ripple-db", "1", "--wp", "5")
    assert proc.returncode == 0, proc.stderr
    direct = json.loads(proc.stdout)
    test = ex4["tests"][5]
    assert test["order"] == 13
    assert test["final"] == direct["final"]
    assert test["mass_estimate_kg"] == direct["mass_estimate"]
    assert test["samples"] == direct["samples"]


def test_ex5_ends_at_the_goal_hovering(result):
    out, _ = result
    summary = json.loads((out / "ex5_summary.json").read_text(encoding="utf-8"))
    assert summary["goal_m"] == [1.0, 1.0, -1.0]
    assert summary["final_position_error_norm_m"] < 0.01
    assert summary["final_thrust_n"] == pytest.approx(1.5 * G, rel=0.001)
    assert 0 < summary["max_error_norms"]["e_p"] < 0.05
    assert set(summary["max_abs_errors"]) == {"e_p", "e_v", "e_r", "e_omega"}


def test_a_missing_binary_is_named(tmp_path):
    missing = tmp_path / "no-such-rotorpilot"
    proc = study("--out", tmp_path / "out", "--binary", missing)
    assert proc.returncode == 2
    assert proc.stderr.startswith("error: ") and str(missing) in proc.stderr


def test_a_failing_run_is_named(tmp_path):
    fake = tmp_path / "rotorpilot"
    fake.write_text("#!/bin/sh\necho 'scenario refused' >&2\nexit 3\n")
    fake.chmod(0o755)
    proc = study("--out", tmp_path / "out", "--only", "ex5", "--binary", fake)
    assert proc.returncode == 2
    error = proc.stderr.splitlines()[-1]
    assert error.startswith("error: `rotorpilot sim ")
    assert "ex5_geometric.toml" in error and "exit status 3" in error and "scenario refused" in error
