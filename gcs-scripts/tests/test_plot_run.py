"""plot_run.py on synthetic run.csv files (no rotorpilot binary needed) and on what rotorpilot writes:
every shipped scenario's run.ulg and run.csv, and the flight logs of `run --log`."""
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest
from script_module import load_script

SCRIPT = pathlib.Path(__file__).resolve().parents[1] / "plot_run.py"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
ALL_FIGURES = ("position.png", "errors.png", "attitude.png", "inputs.png", "rotors.png", "wrench.png", "mass.png")
ESTIMATOR = ("fx_hat", "fy_hat", "fz_hat", "tx_hat", "ty_hat", "tz_hat",
             "fx_true", "fy_true", "fz_true", "tx_true", "ty_true", "tz_true", "mass_hat")


def synthetic_columns(rows, rotors):
    """A take-off, a yaw turn and a wind gust from t = 6 s, in the columns of `rotorpilot sim`."""
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 10.0, rows)

    def noise(scale):
        return scale * rng.standard_normal(rows)

    climb = np.clip(t / 4.0, 0.0, 1.0)
    z_ref = -2.0 * (10 * climb**3 - 15 * climb**4 + 6 * climb**5)
    cols = {"t": t}
    cols.update(x_ref=0.5 * np.sin(0.5 * t), y_ref=np.zeros(rows), z_ref=z_ref)
    cols.update(x=cols["x_ref"] + noise(0.01), y=noise(0.01), z=z_ref + 0.05 * np.exp(-t) + noise(0.005))
    for axis in "xyz":
        cols["e" + axis] = cols[axis] - cols[axis + "_ref"]
        cols["ev" + axis] = np.gradient(cols["e" + axis], t)
    cols.update(roll_ref=np.zeros(rows), pitch_ref=0.05 * np.cos(0.5 * t), yaw_ref=np.where(t > 5, 0.5, 0.0))
    for angle in ("roll", "pitch", "yaw"):
        cols[angle] = cols[angle + "_ref"] + noise(0.01)
    for axis in ("x", "y", "z"):
        cols["eR_" + axis] = noise(0.01)
        cols["ew_" + axis] = noise(0.05)
    cols["thrust"] = 14.7 + 3.0 * np.exp(-t) + noise(0.1)
    for axis in ("x", "y", "z"):
        cols["tau_" + axis] = noise(0.02)
    for i in range(1, rotors + 1):
        cols[f"omega_{i}"] = 600.0 + 20.0 * np.exp(-t) + noise(2.0)
    gust = np.where(t > 6.0, 1.0, 0.0)
    for k, axis in enumerate("xyz"):
        cols[f"f{axis}_true"] = gust * (k + 1) * 0.5
        cols[f"f{axis}_hat"] = cols[f"f{axis}_true"] * (1 - np.exp(-5 * np.clip(t - 6, 0, None))) + noise(0.02)
        cols[f"t{axis}_true"] = gust * 0.01 * (k + 1)
        cols[f"t{axis}_hat"] = cols[f"t{axis}_true"] + noise(0.001)
    cols["mass_hat"] = 1.5 - 0.3 * np.exp(-t)
    cols["saturated"] = ((t > 0.2) & (t < 0.6)).astype(float)
    return cols


def write_run(directory, rows=2000, rotors=4, drop=(), summary=True):
    """Writes run.csv (without the columns in drop) and summary.json into directory."""
    directory.mkdir(parents=True, exist_ok=True)
    cols = {name: values for name, values in synthetic_columns(rows, rotors).items() if name not in drop}
    np.savetxt(directory / "run.csv", np.column_stack(list(cols.values())), delimiter=",",
               header=",".join(cols), comments="", fmt="%.9g")
    if summary:
        (directory / "summary.json").write_text(json.dumps(
            {"controller": "geometric", "airframe": f"{rotors}-rotor", "true_mass_kg": 1.5}))
    return directory


def plot_run(*args):
    """Runs plot_run.py in a subprocess with this interpreter."""
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          timeout=300, check=False)


def assert_png(path):
    """path is a real PNG of more than a few KB."""
    assert path.is_file(), f"{path.name} not written"
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC, f"{path.name} is not a PNG"
    assert len(data) > 5000, f"{path.name} is only {len(data)} bytes"


@pytest.mark.parametrize("rotors", [4, 8])
def test_every_figure_is_rendered(tmp_path, rotors):
    run_dir = write_run(tmp_path / "run", rotors=rotors)
    proc = plot_run(run_dir)
    assert proc.returncode == 0, proc.stderr
    for name in ALL_FIGURES:
        assert_png(run_dir / name)


def test_out_dir_and_dpi(tmp_path):
    run_dir = write_run(tmp_path / "run", rotors=6, summary=False)
    out = tmp_path / "figures" / "nested"
    proc = plot_run(run_dir, "--out", out, "--dpi", "60")
    assert proc.returncode == 0, proc.stderr
    for name in ALL_FIGURES:
        assert_png(out / name)
        assert not (run_dir / name).exists()


def test_without_estimator_columns_skips_wrench_and_mass(tmp_path):
    run_dir = write_run(tmp_path / "run", drop=ESTIMATOR)
    proc = plot_run(run_dir)
    assert proc.returncode == 0, proc.stderr
    for name in ALL_FIGURES[:5]:
        assert_png(run_dir / name)
    assert not (run_dir / "wrench.png").exists() and not (run_dir / "mass.png").exists()
    assert "skipping wrench.png" in proc.stderr and "skipping mass.png" in proc.stderr


def test_missing_directory_exits_2(tmp_path):
    missing = tmp_path / "nope"
    proc = plot_run(missing)
    assert proc.returncode == 2
    assert f"error: {missing}: no such file or directory" in proc.stderr
    proc = plot_run(tmp_path)
    assert proc.returncode == 2 and "no run.ulg, run.csv or log/*/*.ulg" in proc.stderr


def test_empty_cells_are_gaps(tmp_path):
    """run.csv leaves the control columns empty while the motors are off."""
    write_run(tmp_path, rows=50)
    lines = (tmp_path / "run.csv").read_text().splitlines()
    header = lines[0].split(",")
    for i in range(1, 10):
        cells = lines[i].split(",")
        for name in ("ex", "thrust", "tau_z", "fx_hat", "mass_hat"):
            cells[header.index(name)] = ""
        lines[i] = ",".join(cells)
    (tmp_path / "run.csv").write_text("\n".join(lines) + "\n")
    proc = plot_run(tmp_path)
    assert proc.returncode == 0, proc.stderr
    for name in ALL_FIGURES:
        assert_png(tmp_path / name)


@pytest.mark.parametrize("column", ["evy", "omega_3", "tau_z"])
def test_missing_column_exits_2_and_names_it(tmp_path, column):
    run_dir = write_run(tmp_path / "run", drop=(column,))
    proc = plot_run(run_dir)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"error: {run_dir / 'run.csv'}:")
    assert column in proc.stderr


def test_incomplete_estimator_group_exits_2(tmp_path):
    run_dir = write_run(tmp_path / "run", drop=("ty_hat",))
    proc = plot_run(run_dir)
    assert proc.returncode == 2 and "ty_hat" in proc.stderr


@pytest.mark.parametrize("content,message", [
    ("", "empty file"),
    ("t,x,y\n", "missing column"),
])
def test_malformed_file_exits_2(tmp_path, content, message):
    (tmp_path / "run.csv").write_text(content)
    proc = plot_run(tmp_path)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"error: {tmp_path / 'run.csv'}:") and message in proc.stderr


def test_non_numeric_value_exits_2(tmp_path):
    write_run(tmp_path, rows=10)
    lines = (tmp_path / "run.csv").read_text().splitlines()
    lines[4] = "oops," + lines[4].split(",", 1)[1]
    (tmp_path / "run.csv").write_text("\n".join(lines) + "\n")
    proc = plot_run(tmp_path)
    assert proc.returncode == 2 and "not a numeric CSV" in proc.stderr and "oops" in proc.stderr


def test_header_only_exits_2(tmp_path):
    write_run(tmp_path, rows=3)
    header = (tmp_path / "run.csv").read_text().splitlines()[0]
    (tmp_path / "run.csv").write_text(header + "\n")
    proc = plot_run(tmp_path)
    assert proc.returncode == 2 and "no data rows" in proc.stderr


def test_decimation_keeps_extremes_and_bounds_points():
    module = load_script("plot_run")
    y = np.sin(np.linspace(0, 50, 1_000_001))
    y[123_457] = 9.0
    y[777_777] = -9.0
    idx = module.decimation_indices(y, 20_000)
    assert len(idx) <= 20_000
    assert np.all(np.diff(idx) > 0) and idx[0] == 0 and idx[-1] == len(y) - 1
    assert 123_457 in idx and 777_777 in idx
    assert np.array_equal(module.decimation_indices(y[:500], 20_000), np.arange(500))


SCENARIOS = sorted((pathlib.Path(__file__).resolve().parents[2] / "scenarios").glob("*.toml"))
# Plotted from their CSV too: one with the wrench estimate, one without (the CSV reader is the
# same for every scenario; each plot takes a core for several seconds).
FROM_CSV_TOO = {"ex4_estimator", "ex5_geometric"}


@pytest.mark.parametrize("scenario", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_every_shipped_scenario_plots(rotorpilot, tmp_path, scenario):
    out = tmp_path / scenario.stem
    csv = scenario.stem in FROM_CSV_TOO
    sim = rotorpilot("sim", str(scenario), "--out", str(out), *(["--csv"] if csv else []))
    assert sim.returncode == 0, sim.stderr
    summary = json.loads(sim.stdout)
    for run in (out, out / "run.csv") if csv else (out,):
        figures = tmp_path / ("csv" if run.suffix else "ulog")
        proc = plot_run(run, "--out", str(figures))
        assert proc.returncode == 0, proc.stderr
        for name in ALL_FIGURES[:5]:
            assert_png(figures / name)
        assert (figures / "wrench.png").exists() == (summary["estimate"] is not None), proc.stderr


@pytest.mark.rotorpilot(log=True)
def test_a_run_log_directory_plots_its_latest_flight(autopilot):
    autopilot.vehicle.takeoff()
    autopilot.vehicle.sleep(1.0)
    autopilot.vehicle.disarm(force=True)
    assert autopilot.stop() == 0
    (flight,) = autopilot.flight_logs()
    proc = plot_run(autopilot.log_dir)
    assert proc.returncode == 0, proc.stderr
    for name in ALL_FIGURES:
        assert_png(autopilot.log_dir / name)
