"""What the runners of the clients' own examples share (run_mavsdk_examples.py,
run_dronekit_examples.py): an example's process watched to its end, or stopped with Ctrl-C as a
user stops it; a helper process stopped; and their command line (examples by name, speed-up,
time-out, kept runs judged again)."""

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

# An example still running this long after printing a traceback is stopped [s].
RAISED_GRACE_S = 8.0
TRACEBACK = "Traceback (most recent call last)"


def watch(run, lines, started, limit_s, over=124):
    """Waits for the example process `run` (started at monotonic time `started`, its output lines
    gathered into `lines` by a reader thread) to end: its exit code; `over` once `limit_s` wall
    seconds have passed; "raised" when it still runs RAISED_GRACE_S after printing a traceback
    (clients keep their process alive after an uncaught exception). A process still running is
    stopped with Ctrl-C (SIGINT to its process group; SIGKILL after 10 s), noted in `lines`."""
    raised_at, code = None, None
    while code is None:
        time.sleep(0.2)
        if run.poll() is not None:
            code = run.returncode
        elif time.monotonic() - started > limit_s:
            code = over
        elif raised_at is None and any(TRACEBACK in line for line in lines):
            raised_at = time.monotonic()
        elif raised_at is not None and time.monotonic() - raised_at > RAISED_GRACE_S:
            code = "raised"
    if run.poll() is None:
        os.killpg(run.pid, signal.SIGINT)  # Ctrl-C: the whole foreground group
        try:
            run.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(run.pid, signal.SIGKILL)
            run.wait()
        lines.append(f"\n[stopped with Ctrl-C after {time.monotonic() - started:.0f} s]")
    return code


def stop(proc, timeout_s=10):
    """Stops a helper process (the vehicle, a server) with SIGINT, killed after `timeout_s`."""
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        proc.kill()


@dataclass
class Runner:
    """What a runner gives the command line: its examples' `specs`, the default time-out [s],
    `fly(name, speedup, timeout_s, keep)` (a verdict), `fly_inside(name, spec, log_dir, work_dir,
    speedup, timeout_s)` (in the namespace: the exit code and output) and `rejudge(kept)`
    (verdicts of kept runs)."""

    specs: dict
    default_timeout_s: float
    fly: Callable
    fly_inside: Callable
    rejudge: Callable


def main(description, known, runner):
    """The runners' command line: EXAMPLE names (default: every one of `known`), --speedup,
    --timeout, --keep, --rejudge, and the hidden --inside of the namespace, carried out by
    `runner` (a `Runner`). One JSON verdict per example on stdout; exit status 1 when any example
    fails."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("examples", nargs="*", help="example names (default: all)")
    p.add_argument("--speedup", default="1", help="rotorpilot --speedup (default 1; an example's SPECS may override)")
    p.add_argument(
        "--timeout",
        type=float,
        default=runner.default_timeout_s,
        help=f"wall seconds per example (default {runner.default_timeout_s:g})",
    )
    p.add_argument("--keep", help="copy each flight's logs, examples and output to KEEP/EXAMPLE")
    p.add_argument("--rejudge", metavar="KEPT", help="judge the runs kept in KEPT again, flying nothing")
    p.add_argument("--inside", help=argparse.SUPPRESS)
    p.add_argument("--log-dir", help=argparse.SUPPRESS)
    p.add_argument("--work-dir", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.inside:
        spec = runner.specs.get(args.inside, {})
        code, output = runner.fly_inside(args.inside, spec, args.log_dir, args.work_dir, args.speedup, args.timeout)
        sys.stdout.write(f"exit {code}\n{output}")
        return 0
    names = args.examples or known
    unknown = [n for n in names if n not in known]
    if unknown and not args.rejudge:
        p.error(f"unknown example(s) {unknown}; known: {known}")
    verdicts = (
        runner.rejudge(args.rejudge)
        if args.rejudge
        else (runner.fly(name, args.speedup, args.timeout, args.keep) for name in names)
    )
    failed = 0
    for verdict in verdicts:
        print(json.dumps(verdict, ensure_ascii=False), flush=True)
        failed += not verdict["ok"]
    return 1 if failed else 0
