"""`rotorpilot montecarlo` end to end: 30 random recoveries per law on quad_x, every run finite and
panic-free, convergence rates from the measured 1000-run figures with margin, and a report that
depends only on the seed."""
import json

import pytest

RUNS = "30"


def campaign(rotorpilot, *extra):
    proc = rotorpilot("montecarlo", "--runs", RUNS, "--json", *extra)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout, json.loads(proc.stdout)


@pytest.fixture(scope="module")
def default_run(rotorpilot):
    return campaign(rotorpilot, "--seed", "0")


def test_every_run_is_finite_and_panic_free(default_run):
    _, report = default_run
    assert [c["controller"] for c in report["controllers"]] == ["geometric", "hierarchical", "passivity"]
    for c in report["controllers"]:
        assert c["runs"] == 30
        assert c["panics"] == 0, c["failures"]
        assert c["non_finite_runs"] == 0, c["failures"]
        assert c["plant_fault_runs"] == 0
        # Every run is accounted for: converged or listed with its reason and draw.
        assert c["converged"] + len(c["failures"]) == 30
        assert all(f["reason"] in {"outside_tolerance", "controller_fault", "fly_away"} for f in c["failures"])


def test_the_envelope_and_criterion_are_the_documented_defaults(default_run):
    _, report = default_run
    env = report["envelope"]
    assert env["max_tilt_deg"] == pytest.approx(60.0)
    assert (env["max_rate_rad_s"], env["max_speed_m_s"], env["max_offset_m"]) == (3.0, 3.0, 1.0)
    assert env["max_force_n"] == pytest.approx(0.2 * 1.5 * 9.81)
    # 20 % of quad_x's torque authority at hover: 2.396 N·m roll/pitch, 0.813 N·m yaw.
    assert env["max_torque_n_m"] == pytest.approx([0.479, 0.479, 0.163], abs=1e-3)
    assert report["criterion"] == {"position_m": 0.1, "attitude_deg": pytest.approx(5.0), "window_s": 1.0}
    assert report["estimator"] == {"order": 1, "ripple_db": 3.0, "wp_rad_s": 2.0}
    assert report["compensation"] is True and report["heading"] == "zero"


def test_convergence_rates(default_run, rotorpilot):
    # Measured over 1000 runs (docs/cli.md §6): geometric 99.0 %, hierarchical 87.4 %, passivity 81.9 %
    # with a heading change to north; 100 / 99.0 / 99.0 % holding the initial heading.
    _, report = default_run
    rate = {c["controller"]: c["converged_pct"] for c in report["controllers"]}
    assert rate["geometric"] >= 90.0, rate
    assert rate["hierarchical"] >= 70.0 and rate["passivity"] >= 65.0, rate
    for c in report["controllers"]:
        t = c["convergence_time_s"]
        assert 0.0 < t["median"] <= t["p95"] <= t["max"] <= 5.0, c
        assert c["worst_final_position_error_m"] is not None
    _, held = campaign(rotorpilot, "--seed", "0", "--heading", "initial")
    for c in held["controllers"]:
        assert c["converged_pct"] >= 90.0, (c["controller"], c["failures"])
        assert c["panics"] == 0 and c["non_finite_runs"] == 0


def test_the_same_seed_gives_the_same_report(default_run, rotorpilot):
    text, _ = default_run
    again, _ = campaign(rotorpilot, "--seed", "0", "--threads", "1")
    assert again == text, "same seed, one thread instead of several: identical JSON"
    other, report = campaign(rotorpilot, "--seed", "1", "--controller", "geometric")
    assert other != text and len(report["controllers"]) == 1


def test_text_table_and_bad_options(rotorpilot):
    proc = rotorpilot("montecarlo", "--runs", "5", "--controller", "geometric", "--max-tilt", "10")
    assert proc.returncode == 0, proc.stderr
    assert "tilt ≤ 10.0°" in proc.stdout
    assert "geometric" in proc.stdout and "converged" in proc.stdout
    for args, needle in [
        (["--runs", "0"], "--runs"),
        (["--controller", "pid"], "--controller"),
        (["--max-rate", "-1"], "max-rate"),
        (["--max-torque", "1,2"], "--max-torque"),
        (["--duration", "0.5"], "--window"),
        (["--est-wp", "5000"], "estimator"),
    ]:
        proc = rotorpilot("montecarlo", *args)
        assert proc.returncode == 2, (args, proc.stdout)
        assert proc.stderr.startswith("error: ") and needle in proc.stderr, (args, proc.stderr)
