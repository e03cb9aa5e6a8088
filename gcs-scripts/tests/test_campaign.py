"""`python -m rotorpilot_gcs.campaign`: a sweep run on Ray gives the rows `rotorpilot sweep` gives
on one machine; failed shards are retried and reported; a bad sweep file is the binary's message;
the merged parquet has the documented schema. The pure helpers (shards, column order, merge,
staging) without Ray. One local Ray instance of 2 CPUs serves the module's campaigns
(``--address``); one campaign starts its own local instance (the default)."""
import json
import logging
import os
import pathlib
import stat
import subprocess
import sys

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from rotorpilot_gcs import campaign
from rotorpilot_gcs.errors import UsageError

GCS = pathlib.Path(__file__).resolve().parents[1]
ROOT = GCS.parent
EX4 = ROOT / "scenarios" / "ex4_estimator.toml"
AXES = ["estimator.order", "estimator.wp"]
RUNS = 8  # 2 orders × 2 bandwidths × 2 seeds
SWEEP = """\
# Exercise 4 in 1 s: estimator order × passband edge, two seeds each.
scenario = "../scenarios/base.toml"

[seeds]
count = 2

[[axis]]
field = "estimator.order"
values = [1, 3]

[[axis]]
field = "estimator.wp"
values = [2.0, 5.0]
"""
PARQUET_TYPES = {"int64": pa.int64(), "double": pa.float64(), "boolean": pa.bool_(), "string": pa.string()}


def write_sweep(directory, text=SWEEP):
    """sweeps/sweep.toml over scenarios/base.toml (exercise 4 shortened to 1 s) in `directory`:
    the scenario is in a sibling folder, so staging must keep the layout."""
    (directory / "scenarios").mkdir(parents=True, exist_ok=True)
    (directory / "sweeps").mkdir(exist_ok=True)
    base = EX4.read_text()
    assert "duration = 40.0" in base
    (directory / "scenarios" / "base.toml").write_text(base.replace("duration = 40.0", "duration = 1.0", 1))
    path = directory / "sweeps" / "sweep.toml"
    path.write_text(text)
    return path


def run_campaign_cli(*args, address=None, timeout=120):
    """``python -m rotorpilot_gcs.campaign ARGS`` with the package beside these tests."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(GCS), os.environ.get("PYTHONPATH", "")]))
    env.pop("RAY_ADDRESS", None)
    extra = ["--address", address] if address else []
    return subprocess.run([sys.executable, "-m", "rotorpilot_gcs.campaign", *map(str, args), *extra],
                          capture_output=True, text=True, timeout=timeout, env=env, check=False)


def rows(path):
    """The rows of a results.parquet, sorted by run."""
    return sorted(pq.read_table(path).to_pylist(), key=lambda row: row["run"])


@pytest.fixture(scope="module")
def ray_address():
    """A local Ray instance of 2 CPUs for the module's campaigns; its GCS address."""
    import ray

    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    ray.init(address="local", num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level=logging.ERROR)
    try:
        yield ray.get_runtime_context().gcs_address
    finally:
        ray.shutdown()


@pytest.fixture(scope="module")
def outputs(tmp_path_factory, rotorpilot_bin, ray_address):
    """The sweep run by the binary at --jobs 1 and 2, and by the campaign on 3 shards."""
    work = tmp_path_factory.mktemp("campaign")
    sweep = write_sweep(work)
    out = {}
    for jobs in (1, 2):
        out[f"jobs{jobs}"] = work / f"jobs{jobs}"
        proc = subprocess.run([str(rotorpilot_bin), "sweep", str(sweep), "--jobs", str(jobs), "--out",
                               str(out[f"jobs{jobs}"])], capture_output=True, text=True, timeout=120, check=False)
        assert proc.returncode == 0, proc.stderr
    out["ray"] = work / "ray"
    proc = run_campaign_cli(sweep, "--out", out["ray"], "--shards", 3, "--binary", rotorpilot_bin, address=ray_address)
    assert proc.returncode == 0, proc.stderr
    out["summary"], out["stderr"] = json.loads(proc.stdout), proc.stderr
    out["sweep"] = sweep
    return out


def test_the_campaign_gives_the_binarys_rows(outputs):
    single = rows(outputs["jobs1"] / "results.parquet")
    assert [row["run"] for row in single] == list(range(RUNS))
    assert rows(outputs["jobs2"] / "results.parquet") == single
    assert rows(outputs["ray"] / "results.parquet") == single
    # Same columns in the same order, same types.
    assert pq.read_schema(outputs["ray"] / "results.parquet").equals(
        pq.read_schema(outputs["jobs1"] / "results.parquet"), check_metadata=False)
    summary = outputs["summary"]
    assert summary["runs"] == RUNS and summary["ok"] + summary["failed"] == RUNS
    assert summary["shards"] == 3 and summary["retries"] == 0 and summary["workers"] == 2
    assert summary["results"] == str(outputs["ray"] / "results.parquet")
    # Progress on stderr: every shard (3, 3 and 2 runs) done.
    for line in ("shard 0 (runs 0..3) done", "shard 1 (runs 3..6) done", "shard 2 (runs 6..8) done",
                 f"3/3 shards, {RUNS}/{RUNS} runs"):
        assert line in outputs["stderr"], outputs["stderr"]
    record = json.loads((outputs["ray"] / "sweep.json").read_text())
    assert record["engine"] == "ray" and record["runs"] == RUNS and record["complete"] is True
    assert record["sweep"] == str(outputs["sweep"]) and record["workers"] == 2 and record["retries"] == []
    assert [s["runs"] for s in record["shards"]] == [[0, 3], [3, 6], [6, 8]]
    assert all(s["attempts"] == 1 and s["binary_wall_time_s"] >= 0 for s in record["shards"])
    assert record["ray_overhead_per_shard_s"] is not None and record["wall_time_s"] > 0
    assert {"hostname", "ray", "pyarrow"} <= set(record["machine"])


def test_the_parquet_has_the_documented_schema(outputs):
    table = pq.read_table(outputs["ray"] / "results.parquet")
    names = table.column_names
    assert names[:7] == ["run", "point", "seed", *AXES, "status", "error"]
    assert names[7:] == sorted(names[7:]) and "final_position_error_norm_m" in names
    schema = table.schema
    for name, kind in [("run", "int64"), ("point", "int64"), ("seed", "int64"), ("estimator.order", "int64"),
                       ("estimator.wp", "double"), ("status", "string"), ("error", "string"),
                       ("final_position_error_norm_m", "double"), ("max_tilt_deg", "double"), ("exit", "string"),
                       ("compensation", "boolean"), ("estimate.order", "int64"),
                       ("estimate.convergence_time_s", "double")]:
        assert schema.field(name).type == PARQUET_TYPES[kind], name
    assert all(field.nullable for field in schema)
    assert all(field.type in PARQUET_TYPES.values() for field in schema), schema
    data = table.to_pydict()
    assert data["run"] == list(range(RUNS)) and data["point"] == [r // 2 for r in range(RUNS)]
    assert data["seed"] == [0, 1] * 4
    assert data["estimator.order"] == [1, 1, 1, 1, 3, 3, 3, 3]
    assert data["estimator.wp"] == [2.0, 2.0, 5.0, 5.0] * 2
    assert data["status"] == ["ok"] * RUNS and data["error"] == [None] * RUNS
    assert data["exit"] == ["complete"] * RUNS
    assert all(0.0 <= e < 1.0 for e in data["final_position_error_norm_m"])


WRAPPER = """\
#!/bin/sh
# rotorpilot that fails the first call for each --runs range, and every call for a range with a
# file always-RANGE in the marks folder.
marks='{marks}'
runs=
prev=
for arg in "$@"; do
    if [ "$prev" = "--runs" ]; then runs=$arg; fi
    prev=$arg
done
if [ -n "$runs" ]; then
    if [ -e "$marks/always-$runs" ]; then echo "wrapper: runs $runs always fail" >&2; exit 1; fi
    if [ ! -e "$marks/seen-$runs" ]; then
        : > "$marks/seen-$runs"
        echo "wrapper: first call for runs $runs fails" >&2
        exit 1
    fi
fi
exec '{binary}' "$@"
"""


def wrapper(directory, binary):
    """A failing wrapper around `binary` in `directory`, and its marks folder."""
    marks = directory / "marks"
    marks.mkdir()
    path = directory / "rotorpilot-wrapper"
    path.write_text(WRAPPER.format(marks=marks, binary=binary))
    path.chmod(path.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    return path, marks


def test_a_failing_shard_is_retried_and_reported(tmp_path, rotorpilot_bin):
    """Each shard fails once and is resubmitted; the rows are the binary's (a local instance:
    no --address)."""
    sweep = write_sweep(tmp_path)
    fake, _ = wrapper(tmp_path, rotorpilot_bin)
    proc = run_campaign_cli(sweep, "--out", tmp_path / "ray", "--shards", 2, "--retries", 2, "--binary", fake)
    assert proc.returncode == 0, proc.stderr
    for shard, runs in ((0, "0..4"), (1, "4..8")):
        line = (f"shard {shard} (runs {runs}) failed: exit status 1: wrapper: first call for runs {runs} fails; "
                "retry 1/2")
        assert line in proc.stderr, proc.stderr
        assert f"shard {shard} (runs {runs}) done" in proc.stderr
    assert "(local; ray" in proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["retries"] == 2 and summary["runs"] == RUNS
    record = json.loads((tmp_path / "ray" / "sweep.json").read_text())
    assert sorted((r["shard"], r["attempt"]) for r in record["retries"]) == [(0, 1), (1, 1)]
    assert [s["attempts"] for s in record["shards"]] == [2, 2]
    direct = tmp_path / "direct"
    done = subprocess.run([str(rotorpilot_bin), "sweep", str(sweep), "--out", str(direct)], capture_output=True,
                          text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert rows(tmp_path / "ray" / "results.parquet") == rows(direct / "results.parquet")


def test_a_shard_failing_every_attempt_ends_the_campaign(tmp_path, rotorpilot_bin, ray_address):
    sweep = write_sweep(tmp_path)
    fake, marks = wrapper(tmp_path, rotorpilot_bin)
    (marks / "always-4..8").touch()
    proc = run_campaign_cli(sweep, "--out", tmp_path / "ray", "--shards", 2, "--retries", 1, "--binary", fake,
                            address=ray_address)
    assert proc.returncode == 1, proc.stderr
    assert "shard 1 (runs 4..8) failed: exit status 1: wrapper: runs 4..8 always fail; retry 1/1" in proc.stderr
    assert "shard 1 (runs 4..8) failed: exit status 1: wrapper: runs 4..8 always fail; no retries left" in proc.stderr
    assert "error: shard 1 (runs 4..8) failed every attempt; 4 of 8 runs written" in proc.stderr
    assert "Traceback" not in proc.stderr
    # The rows of the shard that succeeded are kept, the campaign marked incomplete.
    assert [row["run"] for row in rows(tmp_path / "ray" / "results.parquet")] == [0, 1, 2, 3]
    record = json.loads((tmp_path / "ray" / "sweep.json").read_text())
    assert record["complete"] is False and record["shards"][1]["failed"] is True
    # Shard 0 failed once (the wrapper's first call), shard 1 on both attempts, the last not retried.
    assert sorted((r["shard"], r["attempt"], r["retried"]) for r in record["retries"]) == [
        (0, 1, True), (1, 1, True), (1, 2, False)]


@pytest.mark.parametrize("text, needles", [
    (SWEEP.replace("scenario =", "metricz = 3\nscenario ="), ["metricz", "line 2"]),
    (SWEEP.replace("count = 2", "count = = 2"), ["line 5"]),
], ids=["unknown field", "bad line"])
def test_a_bad_sweep_file_is_the_binarys_message(tmp_path, rotorpilot, rotorpilot_bin, text, needles):
    sweep = write_sweep(tmp_path, text)
    own = rotorpilot("sweep", sweep, "--plan")
    assert own.returncode == 2
    proc = run_campaign_cli(sweep, "--out", tmp_path / "out", "--binary", rotorpilot_bin)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("error: ") and "Traceback" not in proc.stderr
    assert "sweep.toml" in proc.stderr
    for needle in needles:
        assert needle in proc.stderr, proc.stderr
    # The binary's own message, once.
    assert own.stderr.strip().removeprefix("error: ") in proc.stderr
    assert not (tmp_path / "out").exists()


def test_bad_command_lines_exit_2(tmp_path):
    for args, needle in [
        ([tmp_path / "missing.toml", "--out", tmp_path / "o"], "no such sweep file"),
        ([write_sweep(tmp_path), "--out", tmp_path / "o", "--shards", "0"], "--shards"),
        ([tmp_path / "sweeps" / "sweep.toml", "--out", tmp_path / "o", "--retries", "-1"], "--retries"),
        ([tmp_path / "sweeps" / "sweep.toml", "--out", tmp_path / "o", "--binary", tmp_path / "nope"], "not found"),
    ]:
        proc = run_campaign_cli(*args)
        assert proc.returncode == 2, (args, proc.stderr)
        assert proc.stderr.startswith("error: ") and needle in proc.stderr, (args, proc.stderr)


# --------------------------------------------------------------------------------------------
# The pure helpers


def test_split_runs():
    assert [(s.start, s.stop) for s in campaign.split_runs(10, 3)] == [(0, 4), (4, 7), (7, 10)]
    assert [len(s) for s in campaign.split_runs(3, 8)] == [1, 1, 1]
    assert [s.runs for s in campaign.split_runs(10, shard_size=4)] == ["0..4", "4..8", "8..10"]
    assert [s.index for s in campaign.split_runs(10, shard_size=4)] == [0, 1, 2]
    assert campaign.split_runs(5) == [campaign.Shard(0, 0, 5)]
    assert str(campaign.Shard(3, 12, 16)) == "shard 3 (runs 12..16)"
    for n in (1, 7, 100, 1001):
        for k in (1, 2, 3, 8, 64):
            parts = campaign.split_runs(n, k)
            assert parts[0].start == 0 and parts[-1].stop == n and all(len(p) >= 1 for p in parts)
            assert all(a.stop == b.start for a, b in zip(parts, parts[1:]))
            assert max(map(len, parts)) - min(map(len, parts)) <= 1
    for args in [(10, 0), (10, None, 0), (10, 2, 2), (0, 1)]:
        with pytest.raises(UsageError):
            campaign.split_runs(*args)
    assert campaign.default_shard_count(1000, 2.0) == 8
    assert campaign.default_shard_count(5, 16) == 5 and campaign.default_shard_count(5, 0) == 4


def test_canonical_columns():
    names = ["max_tilt_deg", "status", "b.x", "run", "exit", "error", "a.y", "seed", "point", "estimate.order"]
    assert campaign.canonical_columns(names, ["b.x", "a.y"]) == [
        "run", "point", "seed", "b.x", "a.y", "status", "error", "estimate.order", "exit", "max_tilt_deg"]
    assert campaign.axis_fields({"axes": [{"field": "b.x", "values": [1]}, "a.y"]}) == ["b.x", "a.y"]
    assert campaign.axis_fields({"axes": None}) == []


def test_merge_tables_fills_absent_metrics_and_sorts():
    later = pa.table({"run": [3, 2], "point": [1, 1], "seed": [1, 0], "k.v": [2.0, 2.0], "status": ["ok", "failed"],
                      "error": [None, "boom"], "z_metric": [1.5, None], "a_metric": [7, None]})
    first = pa.table({"run": [0, 1], "point": [0, 0], "seed": [0, 1], "k.v": [1.0, 1.0], "status": ["refused"] * 2,
                      "error": pa.array([None, None], pa.null()), "a_metric": pa.array([None, None], pa.int64())})
    merged = campaign.merge_tables([later, first], ["k.v"])
    assert merged.column_names == ["run", "point", "seed", "k.v", "status", "error", "a_metric", "z_metric"]
    assert merged.column("run").to_pylist() == [0, 1, 2, 3]
    assert merged.column("z_metric").to_pylist() == [None, None, None, 1.5]
    assert merged.schema.field("error").type == pa.string()
    assert merged.schema.field("a_metric").type == pa.int64()
    with pytest.raises(ValueError):
        campaign.merge_tables([], [])


def test_stage_keeps_the_layout(tmp_path):
    sweep = write_sweep(tmp_path / "study")
    airframe = tmp_path / "airframes" / "quad.toml"
    airframe.parent.mkdir()
    airframe.write_text("# airframe\n")
    binary = tmp_path / "bin" / "rotorpilot-build"
    binary.parent.mkdir()
    binary.write_text("#!/bin/sh\n")
    staging = tmp_path / "staging"
    staging.mkdir()
    inputs = [sweep, tmp_path / "study" / "sweeps" / ".." / "scenarios" / "base.toml", airframe]
    rel = campaign.stage(binary, inputs, sweep, staging)
    assert rel == "inputs/study/sweeps/sweep.toml"
    assert (staging / "inputs" / "study" / "scenarios" / "base.toml").read_text().startswith("# Homework")
    assert (staging / "inputs" / "airframes" / "quad.toml").is_file()
    assert os.access(staging / "rotorpilot", os.X_OK)
    with pytest.raises(UsageError, match="not a file"):
        campaign.stage(binary, [tmp_path / "gone.toml"], sweep, tmp_path / "other")


def test_shard_table_checks_what_a_shard_returns(tmp_path):
    shard = campaign.Shard(1, 2, 4)
    sink = pa.BufferOutputStream()
    pq.write_table(pa.table({"run": [2, 3], "status": ["ok", "ok"]}), sink)
    good = {"returncode": 0, "stdout": '{"wall_time_s": 0.5}', "parquet": sink.getvalue().to_pybytes()}
    table, summary = campaign.shard_table(shard, good)
    assert table.num_rows == 2 and summary["wall_time_s"] == 0.5
    with pytest.raises(ValueError, match="exit status 1: last line"):
        campaign.shard_table(shard, {"returncode": 1, "stderr": "first\nlast line\n"})
    with pytest.raises(ValueError, match="timed out"):
        campaign.shard_table(shard, {"returncode": None, "stderr": "timed out after 5 s"})
    with pytest.raises(ValueError, match="not runs 0..2"):
        campaign.shard_table(campaign.Shard(0, 0, 2), good)
    with pytest.raises(ValueError, match="unreadable"):
        campaign.shard_table(shard, {**good, "parquet": b"not parquet"})
    with pytest.raises(ValueError, match="no JSON summary"):
        campaign.shard_table(shard, {**good, "stdout": "done"})
    with pytest.raises(ValueError, match="no results.parquet"):
        campaign.shard_table(shard, {"returncode": 0, "stdout": "{}"})


def test_an_unreachable_cluster_is_named(tmp_path, rotorpilot_bin):
    import socket

    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen()
        campaign.check_reachable(f"127.0.0.1:{server.getsockname()[1]}")
        closed = f"127.0.0.1:{server.getsockname()[1]}"
    for address in ("auto", "ray://head:10001", "local"):
        campaign.check_reachable(address)  # left to Ray
    with pytest.raises(campaign.CampaignError, match="no Ray cluster at 127.0.0.1"):
        campaign.check_reachable(closed)
    proc = run_campaign_cli(write_sweep(tmp_path), "--out", tmp_path / "o", "--binary", rotorpilot_bin,
                            address=closed)
    assert proc.returncode == 1 and proc.stderr.startswith(f"error: no Ray cluster at {closed}"), proc.stderr


def test_run_shard_without_ray(tmp_path, monkeypatch):
    """The task's body in a staged directory: the binary's outputs, or a time-out."""
    monkeypatch.chdir(tmp_path)
    script = tmp_path / "rotorpilot"
    script.write_text('#!/bin/sh\n[ "$4" = "0..2" ] || sleep 5\nprintf "PAR1" > "$8/results.parquet"\n'
                      'echo "{\\"args\\": \\"$*\\"}"\necho progress >&2\n')
    script.chmod(0o755)
    done = campaign.run_shard("inputs/s.toml", 0, 2, timeout=10)
    assert done["returncode"] == 0 and done["parquet"] == b"PAR1" and done["stderr"] == "progress\n"
    args = json.loads(done["stdout"])["args"].split()
    assert args[:7] == ["sweep", "inputs/s.toml", "--runs", "0..2", "--jobs", "1", "--out"]
    assert not pathlib.Path(args[7]).exists(), "the shard's output directory is removed"
    late = campaign.run_shard("inputs/s.toml", 2, 4, timeout=0.3)
    assert late["returncode"] is None and late["stderr"] == "timed out after 0.3 s" and "parquet" not in late
    with pytest.raises(campaign.ShardFailure, match="timed out after 0.3 s"):
        campaign.shard_table(campaign.Shard(1, 2, 4), late)
