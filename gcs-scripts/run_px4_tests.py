#!/usr/bin/env python3
"""Runs PX4's MAVSDK integration cases for multicopters (the port in px4_tests/) against rotorpilot.

This is the counterpart of PX4-Autopilot's test/mavsdk_tests/mavsdk_test_runner.py with
configs/sitl.json: every case gets a fresh vehicle, a wall-clock limit (the config's 10 minutes
by default) and the model its test filter names there (iris for [multicopter]/[offboard] cases:
`--airframe quad_x`; the hexarotors of the [controlallocation] and motor-failure configs:
`hexa_x`). Parameters a config sets at boot (PX4_PARAM_* in a test's "env") go to the vehicle
as a `--params` file. The speed factor is rotorpilot's `--speedup`, as PX4's `--speed-factor`.

Each case runs in its own network namespace (`unshare -n`, so MAVSDK's fixed ports 14540 and
50051 never clash when cases run side by side): `rotorpilot run --airframe A --bind-gcs
127.0.0.1:0 --bind-api 127.0.0.1:0 [--speedup X]` with its default, realistic sensors, which sends
its API link to 127.0.0.1:14540 as PX4 SITL does, and MAVSDK's `System()` connected to
`udpin://0.0.0.0:14540`. One JSON line per case on stdout: {"case", "verdict" ("pass", "FAIL" or
"not applicable"), "error" (the first failed check with the value seen; the others follow in
"failed_checks"), "seconds" (wall time)}. Exit 1 when a case fails.

usage: run_px4_tests.py [CASE ...] [--speedup X] [--timeout S] [--jobs N] [--keep DIR] [--list]
       (CASE: a PX4 case name or a part of one, of its function or of its module; none: all.
       Needs root for unshare -n.)
"""
import argparse
import asyncio
import concurrent.futures
import json
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import traceback

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import px4_tests  # noqa: E402  (after the path: the package sits beside this script)
from rotorpilot_gcs.process import checkout_binary, find_binary  # noqa: E402

#: The config's per-case limit (configs/sitl.json: "timeout_min": 10) [s].
DEFAULT_TIMEOUT_S = 600.0
#: What the namespace wrapper adds to a case's limit before giving up on it [s].
SHUTDOWN_MARGIN_S = 90.0
VERDICT_MARK = "PX4_CASE_VERDICT "


def slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")


def select(cases, patterns):
    """The cases named by `patterns` (whole or part of a case name, function or module; any case)."""
    if not patterns:
        return list(cases)
    chosen, unknown = [], []
    for pattern in patterns:
        p = pattern.lower()
        hits = [c for c in cases if c.name.lower() == p] or [
            c for c in cases if p in c.name.lower() or p in c.run.__name__ or p in c.module]
        if not hits:
            unknown.append(pattern)
        chosen += [c for c in hits if c not in chosen]
    if unknown:
        raise SystemExit(f"no case matches {unknown}; --list shows them")
    return chosen


# --- inside the namespace ----------------------------------------------------------------------
async def run_case(case, timeout_s: float) -> dict:
    from px4_tests import autopilot_tester
    from px4_tests.checks import REPORT, RequireFailed

    problem = None
    try:
        await asyncio.wait_for(case.run(px4_tests.CONNECTION_URL), timeout_s)
    except RequireFailed:
        pass  # recorded in REPORT
    except asyncio.TimeoutError:
        step = autopilot_tester.ACTIVE[-1].step if autopilot_tester.ACTIVE else "starting"
        problem = f"timed out after {timeout_s:.0f} s while {step}"
    except Exception as error:  # a crash of the case itself is a failure too
        problem = f"{type(error).__name__}: {error} ({traceback.format_exc().splitlines()[-3].strip()})"
    finally:
        for tester in autopilot_tester.ACTIVE:
            await tester.close()
    failures = REPORT.summary()
    if problem:
        failures.append(problem)
    return {"failures": failures}


def inside(case, speedup: str, timeout_s: float, log_dir: pathlib.Path) -> dict:
    """Starts the vehicle in this (fresh) namespace, runs the case, stops the vehicle."""
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    command = [str(find_binary(fallback=checkout_binary())), "run", "--airframe", case.airframe, "--bind-gcs",
               "127.0.0.1:0", "--bind-api", "127.0.0.1:0", "--speedup", speedup, "--log", str(log_dir)]
    if case.boot_params:
        params = log_dir / "boot.params"
        params.write_text("".join(f"{name} {value}\n" for name, value in case.boot_params))
        command += ["--params", str(params)]
    with open(log_dir / "vehicle.stderr", "w") as vehicle_log:
        vehicle = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=vehicle_log, text=True)
    try:
        ready = vehicle.stdout.readline()
        if not ready.startswith("{"):
            vehicle.wait(timeout=10)
            return {"failures": [f"rotorpilot did not start (exit {vehicle.returncode}): "
                                 f"{(log_dir / 'vehicle.stderr').read_text()[-400:]}"]}
        threading.Thread(target=vehicle.stdout.read, daemon=True).start()  # keep its pipe drained
        result = asyncio.run(run_case(case, timeout_s))
        if vehicle.poll() is not None:
            result["failures"].append(f"rotorpilot exited with {vehicle.returncode} during the case: "
                                      f"{(log_dir / 'vehicle.stderr').read_text()[-400:]}")
        return result
    finally:
        if vehicle.poll() is None:
            vehicle.send_signal(signal.SIGINT)
            try:
                vehicle.wait(timeout=10)
            except subprocess.TimeoutExpired:
                vehicle.kill()
                vehicle.wait()


# --- outside -------------------------------------------------------------------------------------
def verdict_line(case, failures, seconds, note=None) -> dict:
    if case.not_applicable:
        verdict = {"case": case.name, "verdict": "not applicable", "error": case.not_applicable, "seconds": 0.0}
    else:
        verdict = {"case": case.name, "verdict": "FAIL" if failures else "pass",
                   "error": failures[0] if failures else None, "seconds": round(seconds, 1)}
        if len(failures) > 1:
            verdict["failed_checks"] = failures[1:]
    if case.disabled_upstream:
        verdict["disabled_upstream"] = True
    if note:
        verdict["note"] = note
    return verdict


def fly(case, speedup: str, timeout_s: float, keep) -> dict:
    """Runs one case in a new network namespace; its verdict line."""
    if case.not_applicable:
        return verdict_line(case, [], 0.0)
    scratch = pathlib.Path(tempfile.mkdtemp(prefix=f"px4-{slug(case.name)[:40]}-"))
    started = time.monotonic()
    inner = subprocess.Popen(
        ["unshare", "-n", sys.executable, __file__, "--inside", case.name, "--speedup", speedup,
         "--timeout", str(timeout_s), "--log-dir", str(scratch)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        stdout, stderr = inner.communicate(timeout=timeout_s + SHUTDOWN_MARGIN_S)
    except subprocess.TimeoutExpired:
        os.killpg(inner.pid, signal.SIGKILL)  # the vehicle and mavsdk_server with it
        stdout, stderr = inner.communicate()
        late = f"no verdict within {timeout_s + SHUTDOWN_MARGIN_S:.0f} s"
        stdout += f"\n{VERDICT_MARK}" + json.dumps({"failures": [late]})
    seconds = time.monotonic() - started
    marked = [line[len(VERDICT_MARK):] for line in stdout.splitlines() if line.startswith(VERDICT_MARK)]
    failures = json.loads(marked[-1])["failures"] if marked else [f"no verdict: {stderr.strip()[-600:]}"]
    (scratch / "case.log").write_text(stderr)
    if keep:
        shutil.copytree(scratch, pathlib.Path(keep) / slug(case.name), dirs_exist_ok=True)
    shutil.rmtree(scratch, ignore_errors=True)
    return verdict_line(case, failures, seconds)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("cases", nargs="*", help="case names or parts of them (default: all)")
    p.add_argument("--speedup", default="1", help="rotorpilot --speedup, PX4's --speed-factor (default 1)")
    p.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S,
                   help=f"wall-clock seconds per case (default {DEFAULT_TIMEOUT_S:.0f}, the config's 10 min)")
    p.add_argument("--jobs", type=int, default=1, help="cases run at once, each in its own namespace (default 1)")
    p.add_argument("--keep", help="copy each case's logs (tlog, ULog, vehicle and case output) to KEEP/CASE")
    p.add_argument("--list", action="store_true", help="list the cases and exit")
    p.add_argument("--inside", help=argparse.SUPPRESS)
    p.add_argument("--log-dir", help=argparse.SUPPRESS)
    args = p.parse_args()
    cases = px4_tests.all_cases()
    if args.inside:
        case = next(c for c in cases if c.name == args.inside)
        result = inside(case, args.speedup, args.timeout, pathlib.Path(args.log_dir))
        print(VERDICT_MARK + json.dumps(result), flush=True)
        os._exit(0)  # mavsdk_server and gRPC threads need not be waited for
    chosen = select(cases, args.cases)
    if args.list:
        for c in chosen:
            extra = f" ({c.airframe})" if c.airframe != "quad_x" else ""
            status = " [not applicable]" if c.not_applicable else " [disabled upstream]" if c.disabled_upstream else ""
            print(f"{c.module}: {c.name} {c.tags}{extra}{status}")
        return 0
    failed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(fly, c, args.speedup, args.timeout, args.keep) for c in chosen]
        for future in concurrent.futures.as_completed(futures):
            verdict = future.result()
            print(json.dumps(verdict), flush=True)
            failed += verdict["verdict"] == "FAIL"
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
