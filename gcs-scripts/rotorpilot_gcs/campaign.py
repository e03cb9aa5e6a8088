"""A sweep run on a Ray cluster: ``python -m rotorpilot_gcs.campaign SWEEP.toml --out DIR``.

``rotorpilot sweep`` runs a sweep on one machine (docs/sweep.md). This module spreads the same
runs over the CPUs of a Ray cluster (a local instance by default) and merges what they return
into one ``DIR/results.parquet`` and ``DIR/sweep.json``, identical row for row to what the binary
writes for the whole sweep on one machine. It is a thin layer over the binary:

1. ``rotorpilot sweep SWEEP.toml --plan`` gives the number of runs N and the files the sweep
   reads (``inputs``).
2. The runs 0 … N−1 are cut into contiguous shards (`split_runs`; by default about
   `SHARDS_PER_CPU` per CPU of the cluster, at least one run each).
3. The binary and copies of the inputs (their layout under their common ancestor kept, so
   relative paths inside the sweep and scenario files still resolve) go into a staging directory
   that Ray ships to every worker as the job's ``runtime_env`` ``working_dir`` (`stage`).
4. Each shard is one Ray task (one CPU): ``./rotorpilot sweep inputs/SWEEP.toml --runs A..B
   --jobs 1 --out TMP`` in its working directory, returning the parquet file's bytes
   (`run_shard`).
5. A shard whose task fails (exit status, crash, unreadable or incomplete table, time-out) is
   submitted again, up to ``--retries`` times, each failure reported on stderr; a shard failing
   every time ends the campaign with status 1 after writing the rows the others returned.
6. The shards' tables are concatenated, their columns put in the canonical order (run, point,
   seed, the axes in the plan's order, status, error, the metrics sorted by name) and sorted by
   run (`merge_tables`).

The pure helpers (shards, column order, merge, checking a shard's table) are in
`rotorpilot_gcs.shards`, re-exported here.

Exit statuses: 0 done (runs that failed are rows, not errors), 1 a shard failed every attempt or
the cluster failed, 2 a bad command line or sweep file (the binary's message, naming the file,
line or axis and field). Progress goes to stderr, one JSON summary to stdout.
"""
from __future__ import annotations

import argparse
import importlib
import json
import logging
import os
import pathlib
import platform
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Any, Sequence

from .errors import GcsError, UsageError
from .process import checkout_binary, find_binary
from .shards import (
    LEADING_COLUMNS,
    SHARDS_PER_CPU,
    STATUS_COLUMNS,
    Shard,
    ShardFailure,
    axis_fields,
    canonical_columns,
    default_shard_count,
    merge_tables,
    shard_table,
    split_runs,
)

__all__ = [
    "CampaignError", "LEADING_COLUMNS", "SHARDS_PER_CPU", "STATUS_COLUMNS", "Shard", "ShardFailure", "axis_fields",
    "canonical_columns", "check_reachable", "default_shard_count", "main", "merge_tables", "read_plan",
    "run_campaign", "run_shard", "shard_table", "split_runs", "stage",
]

#: Resubmissions of a failed shard by default.
DEFAULT_RETRIES = 3
#: The binary's name in the staging directory (the workers run ``./rotorpilot``).
BINARY_NAME = "rotorpilot"
#: The folder of the staging directory holding the copies of the sweep's input files.
INPUTS_DIR = "inputs"
#: The characters of a failed shard's stderr kept in its report.
STDERR_TAIL = 2000
#: Time for a ``HOST:PORT`` cluster address to accept a connection [s].
CONNECT_TIMEOUT_S = 5.0
#: How the extra is installed when ray or pyarrow is missing.
INSTALL_HINT = "pip install 'rotorpilot-gcs[campaign]' (or -r gcs-scripts/requirements.txt)"


class CampaignError(GcsError):
    """The campaign could not finish: a shard failed every attempt, or the binary or the cluster
    did something unexpected (exit status 1)."""


def stage(binary: pathlib.Path, inputs: Sequence[str | os.PathLike[str]], sweep: str | os.PathLike[str],
          directory: pathlib.Path) -> str:
    """Fills `directory` (the job's working directory) with the `binary` as ``rotorpilot`` and
    copies of the `inputs` under ``inputs/``, laid out as under their common ancestor; returns the
    sweep file's path relative to `directory`. `UsageError` for an input that is not a file."""
    # Absolute and normalised as the binary lists them (symbolic links kept, like its paths).
    paths = [pathlib.Path(os.path.abspath(p)) for p in inputs]
    sweep_path = pathlib.Path(os.path.abspath(sweep))
    if sweep_path not in paths:
        paths.append(sweep_path)
    for path in paths:
        if not path.is_file():
            raise UsageError(f"the sweep reads {path}, which is not a file")
    root = pathlib.Path(os.path.commonpath([str(p.parent) for p in paths]))
    for path in paths:
        target = directory / INPUTS_DIR / path.relative_to(root)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(path, target)
    shutil.copy2(binary, directory / BINARY_NAME)
    (directory / BINARY_NAME).chmod(0o755)
    return (pathlib.Path(INPUTS_DIR) / sweep_path.relative_to(root)).as_posix()


def machine() -> dict[str, Any]:
    """The driver's machine and library versions, for ``sweep.json``."""
    info: dict[str, Any] = {"hostname": socket.gethostname(), "platform": platform.platform(),
                            "cpus": os.cpu_count(), "python": platform.python_version()}
    for name in ("ray", "pyarrow"):
        try:
            info[name] = __import__(name).__version__
        except ImportError:
            pass
    return info


# --------------------------------------------------------------------------------------------
# The binary


def read_plan(binary: pathlib.Path, sweep: pathlib.Path) -> dict[str, Any]:
    """``rotorpilot sweep SWEEP --plan``: the plan object. `UsageError` with the binary's message
    for a bad sweep file (its exit status 2), `CampaignError` for anything else."""
    argv = [str(binary), "sweep", str(sweep), "--plan"]
    proc = subprocess.run(argv, capture_output=True, text=True, stdin=subprocess.DEVNULL, check=False)
    message = proc.stderr.strip()
    if message.startswith("error: "):
        message = message[len("error: "):]
    if proc.returncode == 2:
        raise UsageError(message or f"{binary} sweep --plan refused {sweep}")
    if proc.returncode != 0:
        raise CampaignError(f"{binary} sweep --plan exited with status {proc.returncode}: {message}")
    try:
        plan: dict[str, Any] = json.loads(proc.stdout)
        runs = int(plan["runs"])
    except (ValueError, KeyError, TypeError):
        raise CampaignError(f"{binary} sweep --plan printed no plan: {proc.stdout[:200]!r}") from None
    if runs < 1:
        raise CampaignError(f"{binary} sweep --plan counts {runs} runs")
    return plan


def run_shard(sweep: str, start: int, stop: int, timeout: float | None = None) -> dict[str, Any]:
    """The body of a shard's Ray task, run in the job's working directory (see `stage`):
    ``./rotorpilot sweep SWEEP --runs START..STOP --jobs 1 --out TMP``. Returns its exit status,
    stdout, the end of its stderr, the bytes of ``results.parquet`` (exit status 0) and times.
    Needs nothing but the standard library on the worker."""
    started = time.time()
    out = tempfile.mkdtemp(prefix="rotorpilot-shard-")
    try:
        binary = os.path.abspath(BINARY_NAME)
        argv = [binary, "sweep", sweep, "--runs", f"{start}..{stop}", "--jobs", "1", "--out", out]
        result: dict[str, Any] = {"node": socket.gethostname(), "started": started}
        try:
            proc = subprocess.run(argv, capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=timeout,
                                  check=False)
        except subprocess.TimeoutExpired:
            result.update(returncode=None, stdout="", stderr=f"timed out after {timeout:g} s")
        else:
            result.update(returncode=proc.returncode, stdout=proc.stdout, stderr=proc.stderr[-STDERR_TAIL:])
            if proc.returncode == 0 and os.path.isfile(os.path.join(out, "results.parquet")):
                with open(os.path.join(out, "results.parquet"), "rb") as f:
                    result["parquet"] = f.read()
        result["task_time_s"] = time.time() - started
        return result
    finally:
        shutil.rmtree(out, ignore_errors=True)


# --------------------------------------------------------------------------------------------
# Ray


def _progress(text: str) -> None:
    """One progress line on stderr."""
    print(f"campaign: {text}", file=sys.stderr, flush=True)


def _import_ray() -> Any:
    """The ray module, after checking that pyarrow is there too (`UsageError` saying how to
    install them otherwise)."""
    try:
        importlib.import_module("pyarrow")
        return importlib.import_module("ray")
    except ImportError as e:
        raise UsageError(f"the campaign needs ray and pyarrow ({e.name} is missing): {INSTALL_HINT}") from None


def _reason(error: BaseException) -> str:
    """One line about a failed task (a Ray error's message ends with the task's exception)."""
    lines = [line.strip() for line in str(error).strip().splitlines() if line.strip()]
    return f"{type(error).__name__}: {lines[-1] if lines else ''}".rstrip(": ")


def check_reachable(address: str, timeout: float = CONNECT_TIMEOUT_S) -> None:
    """`CampaignError` when nothing accepts a TCP connection at a ``HOST:PORT`` `address` (Ray
    itself would retry for minutes); other forms (``auto``, ``ray://...``) are left to Ray."""
    host, sep, port = address.rpartition(":")
    if not sep or not host or "://" in address or not port.isdigit():
        return
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=timeout).close()
    except OSError as e:
        raise CampaignError(f"no Ray cluster at {address}: {e}") from None


def _init_ray(ray: Any, address: str | None, working_dir: pathlib.Path) -> str:
    """Connects to the cluster at `address`, or starts a local instance on every CPU, with
    `working_dir` as the job's working directory; returns what it connected to."""
    options: dict[str, Any] = {"runtime_env": {"working_dir": str(working_dir)}, "log_to_driver": False,
                               "logging_level": logging.ERROR}
    if address:
        check_reachable(address)
    try:
        if address:
            ray.init(address=address, **options)
            return address
        # A local instance sends no usage statistics (the machine may have no network).
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
        ray.init(address="local", num_cpus=os.cpu_count() or 1, include_dashboard=False, **options)
        return "local"
    except Exception as e:  # Ray raises ConnectionError, RuntimeError, ValueError... with a message
        what = f"reach Ray at {address}" if address else "start a local Ray instance"
        raise CampaignError(f"could not {what}: {_reason(e)}") from None


def run_campaign(sweep: str | os.PathLike[str], out: str | os.PathLike[str], *, binary: pathlib.Path,
                 address: str | None = None, shards: int | None = None, shard_size: int | None = None,
                 retries: int = DEFAULT_RETRIES, shard_timeout: float | None = None) -> dict[str, Any]:
    """Runs the sweep at `sweep` on Ray (`address`, or a local instance) and writes
    ``out/results.parquet`` and ``out/sweep.json``; returns the summary printed on stdout.
    `UsageError` for bad arguments or a bad sweep file, `CampaignError` when a shard failed
    every attempt (the rows of the others are written first)."""
    t0 = time.monotonic()
    if retries < 0:
        raise UsageError(f"--retries is {retries}; it must be at least 0")
    sweep_path = pathlib.Path(sweep)
    if not sweep_path.is_file():
        raise UsageError(f"{sweep}: no such sweep file")
    plan = read_plan(binary, sweep_path)
    runs, axes = int(plan["runs"]), axis_fields(plan)
    if shards is not None or shard_size is not None:
        split_runs(runs, shards, shard_size)  # bad values refused before the cluster starts
    ray = _import_ray()
    out_dir = pathlib.Path(out)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "results.parquet").unlink(missing_ok=True)  # never an older campaign's rows
    staging = pathlib.Path(tempfile.mkdtemp(prefix="rotorpilot-campaign-"))
    try:
        inputs = plan.get("inputs") or [plan["sweep"], plan["scenario"]]
        sweep_rel = stage(binary, inputs, plan.get("sweep", sweep_path), staging)
        connected = _init_ray(ray, address, staging)
        try:
            if __name__ != "__main__":  # functions of __main__ are pickled by value anyway
                # The workers need not import rotorpilot_gcs: `run_shard` travels by value.
                ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])
            cpus = ray.cluster_resources().get("CPU", 1)
            nodes = sum(1 for node in ray.nodes() if node.get("Alive"))
            parts = split_runs(runs, shards if shards or shard_size else default_shard_count(runs, cpus), shard_size)
            _progress(f"{runs} runs in {len(parts)} shards on {int(cpus)} CPUs of {nodes} node(s) ({connected}; "
                      f"ray {ray.__version__}, started in {time.monotonic() - t0:.1f} s)")
            done, retried, failed = _run_shards(ray, parts, sweep_rel, retries, shard_timeout)
        finally:
            ray.shutdown()
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    wall = time.monotonic() - t0
    return _write(out_dir, plan, axes, parts, done, retried, failed, wall, int(cpus), nodes, connected)


def _run_shards(ray: Any, parts: list[Shard], sweep_rel: str, retries: int, timeout: float | None
                ) -> tuple[dict[int, dict[str, Any]], list[dict[str, Any]], list[Shard]]:
    """Submits every shard, resubmits failed ones up to `retries` times, reports progress.
    Returns the finished shards' records (index → table, attempts, node, times), every failed
    attempt (retried or not) and the shards that failed every attempt."""
    task = ray.remote(num_cpus=1, max_retries=0)(run_shard)
    pending: dict[Any, tuple[Shard, int]] = {}
    total = sum(len(s) for s in parts)

    def submit(shard: Shard, attempt: int) -> None:
        pending[task.remote(sweep_rel, shard.start, shard.stop, timeout)] = (shard, attempt)

    for shard in parts:
        submit(shard, 0)
    done: dict[int, dict[str, Any]] = {}
    retried: list[dict[str, Any]] = []
    failed: list[Shard] = []
    start, runs_done = time.monotonic(), 0
    try:
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            shard, attempt = pending.pop(ready[0])
            try:
                result = ray.get(ready[0])
                received = time.time()
                table, summary = shard_table(shard, result)
            except Exception as e:  # a Ray error (crash, runtime env) or the shard's own failure
                reason = str(e) if isinstance(e, ShardFailure) else _reason(e)
                retried.append({"shard": shard.index, "runs": [shard.start, shard.stop], "attempt": attempt + 1,
                                "reason": reason, "retried": attempt < retries})
                if attempt < retries:
                    _progress(f"{shard} failed: {reason}; retry {attempt + 1}/{retries}")
                    submit(shard, attempt + 1)
                else:
                    _progress(f"{shard} failed: {reason}; no retries left")
                    failed.append(shard)
                continue
            binary_s = float(summary.get("wall_time_s") or 0.0)
            done[shard.index] = {"table": table, "attempts": attempt + 1, "node": result.get("node"),
                                 "binary_wall_time_s": round(binary_s, 4),
                                 "task_time_s": round(float(result.get("task_time_s") or 0.0), 4),
                                 "shard_wall_time_s": round(received - float(result["started"]), 4)}
            runs_done += len(shard)
            elapsed = time.monotonic() - start
            _progress(f"{shard} done: {len(done)}/{len(parts)} shards, {runs_done}/{total} runs, "
                      f"{runs_done / max(elapsed, 1e-9):.1f} runs/s")
    except BaseException:  # Ctrl-C: the shards still queued or running are cancelled
        for ref in pending:
            try:
                ray.cancel(ref, force=True)
            except Exception:
                pass
        raise
    return done, retried, failed


def _write(out_dir: pathlib.Path, plan: dict[str, Any], axes: list[str], parts: list[Shard],
           done: dict[int, dict[str, Any]], retried: list[dict[str, Any]], failed: list[Shard], wall: float,
           cpus: int, nodes: int, connected: str) -> dict[str, Any]:
    """Merges the finished shards into ``results.parquet``, writes ``sweep.json``; the summary.
    `CampaignError` after writing when a shard failed every attempt."""
    import pyarrow.parquet as pq

    results = out_dir / "results.parquet"
    table = merge_tables([done[i]["table"] for i in sorted(done)], axes) if done else None
    rows = table.num_rows if table is not None else 0
    statuses = table.column("status").to_pylist() if table is not None else []
    ok = statuses.count("ok")
    if table is not None:
        pq.write_table(table, results)
    overheads = [d["shard_wall_time_s"] - d["binary_wall_time_s"] for d in done.values()]
    # The binary's counts: failed is every run not ok, refused and panicked are among them.
    summary = {"runs": rows, "ok": ok, "failed": rows - ok, "refused": statuses.count("refused"),
               "panicked": statuses.count("panicked"), "wall_time_s": round(wall, 3),
               "runs_per_s": round(rows / wall, 3) if wall > 0 else None, "results": str(results),
               "shards": len(parts), "retries": sum(r["retried"] for r in retried), "workers": cpus}
    if failed:
        summary["missing_runs"] = [[s.start, s.stop] for s in failed]
    record = dict(plan)
    record.update(
        engine="ray", address=connected,
        shards=[{"shard": s.index, "runs": [s.start, s.stop],
                 **({k: v for k, v in done[s.index].items() if k != "table"} if s.index in done else {"failed": True})}
                for s in parts],
        retries=retried, workers=cpus, nodes=nodes, ok=ok, failed=rows - ok, refused=summary["refused"],
        panicked=summary["panicked"], wall_time_s=summary["wall_time_s"],
        runs_per_s=summary["runs_per_s"], complete=not failed,
        ray_overhead_per_shard_s=round(statistics.fmean(overheads), 4) if overheads else None,
        machine=machine())
    (out_dir / "sweep.json").write_text(json.dumps(record, indent=2) + "\n")
    if failed:
        names = ", ".join(str(s) for s in failed)
        raise CampaignError(f"{names} failed every attempt; {rows} of {int(plan['runs'])} runs written to {results}")
    return summary


# --------------------------------------------------------------------------------------------
# Command line


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """The command line of ``python -m rotorpilot_gcs.campaign``."""
    parser = argparse.ArgumentParser(
        prog="python -m rotorpilot_gcs.campaign",
        description="Run a rotorpilot sweep on a Ray cluster (a local instance by default): the same "
                    "results.parquet and sweep.json as `rotorpilot sweep SWEEP --out DIR`.")
    parser.add_argument("sweep", type=pathlib.Path, help="the sweep file (TOML, docs/sweep.md)")
    parser.add_argument("--out", type=pathlib.Path, required=True, help="output directory (created if missing)")
    parser.add_argument("--address", default=os.environ.get("RAY_ADDRESS") or None,
                        help="the Ray cluster to use (default $RAY_ADDRESS, else a local instance on every CPU)")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--shards", type=int, help=f"number of shards (default {SHARDS_PER_CPU} per CPU of the cluster)")
    size.add_argument("--shard-size", type=int, help="runs per shard")
    parser.add_argument("--retries", type=int, default=DEFAULT_RETRIES,
                        help=f"resubmissions of a failed shard (default {DEFAULT_RETRIES})")
    parser.add_argument("--shard-timeout", type=float, default=None, metavar="SECONDS",
                        help="stop a shard's binary after this long (a failure, retried; default none)")
    parser.add_argument("--binary", default=None,
                        help="the rotorpilot binary (default $ROTORPILOT_BIN, else the checkout's "
                             "target/release/rotorpilot)")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    """Runs the command line; prints the summary as JSON on stdout."""
    args = parse_args(argv)
    try:
        binary = find_binary(args.binary, fallback=checkout_binary())
    except FileNotFoundError as e:
        raise UsageError(str(e)) from None
    summary = run_campaign(args.sweep, args.out, binary=binary.resolve(), address=args.address, shards=args.shards,
                           shard_size=args.shard_size, retries=args.retries, shard_timeout=args.shard_timeout)
    print(json.dumps(summary), flush=True)
    return 0


if __name__ == "__main__":
    from .cli import script_main

    script_main(main)
