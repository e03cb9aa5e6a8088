"""plot_sweep.py on a small results.parquet written here (no binary): a PNG, the default panels
and hue, runs that went wrong marked, unknown columns refused with status 2."""
import pathlib
import subprocess
import sys

import pyarrow as pa
import pyarrow.parquet as pq
from script_module import load_script

SCRIPT = pathlib.Path(__file__).resolve().parents[1] / "plot_sweep.py"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def write_results(directory):
    """Estimator order 1, 7, 13 × Ts 1 ms, 2 ms × 2 seeds; order 13 at 1 ms fails (no metrics) on
    seed 0 and diverges on seed 1."""
    rows = []
    for order in (1, 7, 13):
        for dt in (0.001, 0.002):
            for seed in (0, 1):
                run = len(rows)
                row = {"run": run, "point": run // 2, "seed": seed, "estimator.order": order, "dt_s": dt,
                       "status": "ok", "error": None, "estimate.convergence_time_s": 3.0 / order + seed * 0.1,
                       "exit": "complete", "final_position_error_norm_m": 0.01 * order * dt * 1000, "label": "x"}
                if order == 13 and dt == 0.001:
                    if seed == 0:
                        row.update({"status": "failed", "error": "non-finite state", "exit": None,
                                    "estimate.convergence_time_s": None, "final_position_error_norm_m": None})
                    else:
                        row.update({"exit": "diverged", "estimate.convergence_time_s": 9.0})
                rows.append(row)
    schema = pa.schema([("run", pa.int64()), ("point", pa.int64()), ("seed", pa.int64()),
                        ("estimator.order", pa.int64()), ("dt_s", pa.float64()), ("status", pa.string()),
                        ("error", pa.string()), ("estimate.convergence_time_s", pa.float64()), ("exit", pa.string()),
                        ("final_position_error_norm_m", pa.float64()), ("label", pa.string())])
    directory.mkdir(parents=True, exist_ok=True)
    pq.write_table(pa.Table.from_pylist(rows, schema=schema), directory / "results.parquet")
    return rows


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          timeout=120, check=False)


def test_it_writes_a_png(tmp_path):
    write_results(tmp_path / "sweep")
    proc = run(tmp_path / "sweep")
    assert proc.returncode == 0, proc.stderr
    png = tmp_path / "sweep" / "sweep.png"
    assert proc.stdout.strip() == str(png)
    assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > 10_000
    other = tmp_path / "figs" / "order.png"
    proc = run(tmp_path / "sweep", "--x", "dt_s", "--y", "final_position_error_norm_m", "--hue", "none",
               "--out", other)
    assert proc.returncode == 0, proc.stderr
    assert other.read_bytes()[:8] == PNG_MAGIC
    trade = tmp_path / "figs" / "trade.png"
    proc = run(tmp_path / "sweep", "--x", "final_position_error_norm_m", "--y", "estimate.convergence_time_s",
               "--hue", "estimator.order", "--out", trade)
    assert proc.returncode == 0, proc.stderr
    assert trade.read_bytes()[:8] == PNG_MAGIC


def test_a_trade_off_against_a_metric_draws_dots_only(monkeypatch, tmp_path):
    module = load_script("plot_sweep")
    table = pa.Table.from_pylist([
        {"run": i, "point": i, "seed": 0, "estimator.order": i % 2 + 1, "status": "ok", "error": None,
         "exit": "complete", "overshoot": float(i), "time": 10.0 - i} for i in range(6)])
    drawn = []
    import matplotlib.axes

    original = matplotlib.axes.Axes.plot

    def spy(self, *args, **kwargs):
        drawn.append(args[2] if len(args) > 2 else None)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.axes.Axes, "plot", spy)
    module.plot(table, "overshoot", ["time"], "estimator.order", tmp_path / "a.png")
    assert "-" not in drawn and drawn.count("o") == 2, drawn
    drawn.clear()
    module.plot(table, "estimator.order", ["time"], None, tmp_path / "b.png")
    assert "-" in drawn, "against an axis the mean is a line"


def test_defaults_and_marks(tmp_path):
    module = load_script("plot_sweep")
    rows = write_results(tmp_path)
    table = module.load(tmp_path)
    assert module.axes_of(table) == ["estimator.order", "dt_s"]
    assert module.default_metrics(table) == ["estimate.convergence_time_s", "final_position_error_norm_m"]
    bad = module.bad_rows(table)
    assert [r["run"] for r, b in zip(rows, bad) if b] == [8, 9]
    assert module.positions(["a", "b", "a"]) == ([0.0, 1.0, 0.0], ["a", "b"])
    xs, labels = module.positions([1, None, 2.5])
    assert labels is None and xs[0] == 1.0 and xs[1] != xs[1] and xs[2] == 2.5


def test_bad_input_exits_2(tmp_path):
    proc = run(tmp_path / "empty")
    assert proc.returncode == 2 and "results.parquet: no such file" in proc.stderr
    write_results(tmp_path)
    for args, needle in [(["--x", "nope"], "no x column 'nope'"), (["--y", "label"], "not numeric"),
                         (["--hue", "colour"], "no hue column")]:
        proc = run(tmp_path, *args)
        assert proc.returncode == 2 and needle in proc.stderr, (args, proc.stderr)
