#!/usr/bin/env python3
"""Flies DroneKit-Python's own examples, unchanged, against rotorpilot's ArduCopter personality and
judges each flight from the vehicle's tlog.

Each example runs in its own network namespace (`unshare -n`, root), so the fixed port of the
examples' `--connect udpin:127.0.0.1:14550` never clashes, against a fresh `rotorpilot run
--autopilot ardupilot --home=-35.363261,149.165230,584 --log DIR` on the default configuration
(realistic sensors, as ArduPilot SITL) whose GCS link sends to 127.0.0.1:14550, its default. The
home is ArduPilot SITL's default (CMAC, Canberra): the examples' absolute targets (simple_goto's
points, mission_import_export's plan) lie around it, some 200 m away as intended. The examples are
DroneKit-Python's (Apache-2.0, tests/third_party/dronekit_examples/LICENSE, README.txt names the
commit) as published, with dronekit2 3.0.0, the maintained fork (gcs-scripts/requirements.txt).

Each example runs as a user runs it: `python3 NAME.py --connect udpin:127.0.0.1:14550` in a scratch
copy of its directory (so mission_import_export finds mpmission.txt and writes its export there,
create_attribute imports my_vehicle.py). An example that raises is given example_runs.RAISED_GRACE_S to exit;
one still running after its time-out is stopped with Ctrl-C (SIGINT to its process group). When
the example has left the vehicle returning or landing (RTL, LAND), the runner watches the
vehicle's HEARTBEAT on the freed port 14550, as a user watches the ground station after the
script ended, until it disarms (`settle_s` simulated seconds at most); `linger_s` keeps the
vehicle running a little after the example, for the telemetry that answers its last message.

The flight is judged on what a ground station saw: the telemetry in the vehicle's tlog
(`DIR/flight.tlog`), read by `tlog_judge.py`, never the simulator's truth. ArduCopter sends no
EXTENDED_SYS_STATE: the landed state is HEARTBEAT.system_status (STANDBY on the ground, ACTIVE in
the air), given to tlog_judge's landing analysis. Generic checks (tlog_judge.ground_checks):
LOCAL_POSITION_NED.z within 0.1 m of 0 before the first arming, never disarmed more than 0.5 m up,
after every landing resting within 0.2 m of 0 (LOCAL_POSITION_NED and relative_alt), a touch-down
of at most 1 m/s, and where the example lands (RTL, LAND), the end on the ground and the disarm.
Per example (`SPECS`, from what its source asks; modes are HEARTBEAT.custom_mode, ArduCopter's
numbers): the take-off height, each goto target approached (distance from GLOBAL_POSITION_INT), the
speed asked for each leg, RTL and the return home, the attitude example's height and its refused
leaning moves, the channel overrides shown in RC_CHANNELS, the RAW_IMU printed, every command
answered, home and modes set, the mission uploaded, flown and downloaded. Each check reports the
values seen.

Verdicts: "works" when the example exits as it does against ArduCopter and every check holds;
"expected refusal" when it fails where it fails against ArduCopter 4.5 too (the failure is
checked); "pending" when what fails needs a vehicle feature not built yet (`pending`: the checks
that wait for it, with why); "FAIL" otherwise. An example may list `gaps`: checks of a secondary
thing it asks that the vehicle does not do yet (with why); they are reported in `gaps`, not failed.
A pending example that now works, or a gap that now holds, makes the verdict say so ("update
SPECS"). One JSON line per example on stdout; exit 1 when any example fails.

usage: run_dronekit_examples.py [EXAMPLE ...] [--speedup X] [--timeout S] [--keep DIR]
       (no EXAMPLE: every example in tests/third_party/dronekit_examples/; needs root for unshare -n)
       run_dronekit_examples.py --rejudge DIR    (the runs kept in DIR judged again, nothing flown)
"""

import json
import pathlib
import shutil
import subprocess
import sys
import tempfile
import threading
import time

import example_runs as runs
import tlog_judge as judge
from dronekit_seen import (
    CONNECT,
    EXAMPLES,
    HOME,
    RETURNING,
    Seen,
)
from dronekit_specs import (
    SPECS,
)
from rotorpilot_gcs import find_binary
from rotorpilot_gcs.process import checkout_binary
from tlog_judge import Check


def binary():
    """The rotorpilot binary: ROTORPILOT_BIN, else the checkout's target/release/rotorpilot, else
    rotorpilot on PATH (rotorpilot_gcs.find_binary)."""
    return find_binary(fallback=checkout_binary())


def settle(limit_s):
    """After the example: watches the vehicle's HEARTBEAT on the GCS port while it is armed in RTL
    or LAND, until it disarms or `limit_s` wall seconds pass; the seconds watched."""
    from rotorpilot_gcs import connection_with_dialect

    started = time.monotonic()
    link = connection_with_dialect(CONNECT, "ardupilotmega")
    try:
        while time.monotonic() - started < limit_s:
            m = link.recv_match(type="HEARTBEAT", blocking=True, timeout=1.0)
            if m is not None and (m.get_srcSystem(), m.get_srcComponent()) == judge.VEHICLE:
                if not m.base_mode & judge.ARMED_FLAG or m.custom_mode not in RETURNING:
                    break
    finally:
        link.close()
    return time.monotonic() - started


def fly_inside(example, spec, log_dir, work_dir, speedup, timeout_s):
    """In the namespace: starts the vehicle, runs the example; the example's exit code (124: stopped
    at its time-out, "raised": stopped after a traceback) and output."""
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    argv = [
        str(binary()),
        "run",
        "--autopilot",
        "ardupilot",
        "--home=" + ",".join(str(x) for x in HOME),
        "--bind-gcs",
        "127.0.0.1:0",
        "--bind-api",
        "127.0.0.1:0",
        "--log",
        str(log_dir),
        "--speedup",
        str(speedup),
    ]
    vehicle = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        ready = json.loads(vehicle.stdout.readline())
        assert ready.get("event") == "ready", ready
        run = subprocess.Popen(
            [sys.executable, f"{example}.py", "--connect", CONNECT],
            cwd=work_dir,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        lines = []
        reader = threading.Thread(target=lambda: lines.extend(iter(run.stdout.readline, "")), daemon=True)
        reader.start()
        started = time.monotonic()
        code = runs.watch(run, lines, started, timeout_s)
        reader.join(timeout=5)
        if spec.get("settle_s"):
            watched = settle(float(spec["settle_s"]) / float(speedup))
            lines.append(f"\n[vehicle watched {watched:.0f} s after the example]\n")
        time.sleep(spec.get("linger_s", 0.0))
        output = "".join(lines)
    finally:
        runs.stop(vehicle)
    return code, output


def fly(example, speedup, timeout_s, keep):
    """Runs one example in a new network namespace; its verdict as a dict."""
    spec = SPECS.get(example, {})
    speedup = spec.get("speedup", speedup)
    timeout_s = spec.get("timeout_s", timeout_s)
    scratch = pathlib.Path(tempfile.mkdtemp(prefix=f"rp-dk-{example}-"))
    log_dir, work_dir = scratch / "log", scratch / "work"
    shutil.copytree(EXAMPLES / example, work_dir)
    inner = subprocess.run(
        [
            "unshare",
            "-n",
            sys.executable,
            __file__,
            "--inside",
            example,
            "--log-dir",
            str(log_dir),
            "--work-dir",
            str(work_dir),
            "--speedup",
            str(speedup),
            "--timeout",
            str(timeout_s),
        ],
        capture_output=True,
        text=True,
        timeout=timeout_s + 60 + spec.get("settle_s", 0) / float(speedup),
        check=False,
    )
    lines = inner.stdout.splitlines()
    code = lines[0][5:] if lines and lines[0].startswith("exit ") else f"runner {inner.returncode}"
    output = "\n".join(lines[1:]) + inner.stderr
    verdict = judge_run(example, code, output, log_dir, work_dir)
    verdict["speedup"] = speedup
    if keep:
        shutil.copytree(scratch, pathlib.Path(keep) / example, dirs_exist_ok=True)
        pathlib.Path(keep, example, "output.txt").write_text(output)
        pathlib.Path(keep, example, "exit.txt").write_text(code)
    shutil.rmtree(scratch, ignore_errors=True)
    return verdict


def judge_run(example, code, output, log_dir, work_dir):
    """The verdict of one run from its exit `code`, its `output`, the vehicle's tlog in `log_dir`
    and what the example left in `work_dir`."""
    spec = SPECS.get(example, {})
    expect = spec.get("expect", "works")
    verdict = {"example": example, "exit": code, "expect": expect}
    want = spec.get("exit", "0")
    checks = [
        Check(
            "exit",
            code == want,
            f"exit {code} (expected {want})" + ("" if code == want or code != "0" else ": it succeeded, update SPECS"),
        )
    ]
    tlog = pathlib.Path(log_dir, "flight.tlog")
    values = {}
    if not tlog.exists():
        checks.append(Check("flight log", False, "no flight.tlog"))
    else:
        tel, seen = judge.Telemetry(tlog), Seen(tlog)
        tel.landed = seen.landed_states(tel)
        summary = judge.summarize(tel)
        verdict.update(
            {
                k: v
                for k, v in summary.items()
                if k not in ("counts", "statustexts", "command_acks", "orbit_radius_m", "param_count")
            }
        )
        checks += judge.ground_checks(summary, spec.get("lands", False), spec.get("disarms", False))
        if "check" in spec:
            more, values = spec["check"](tel, seen, summary, output, work_dir)
            checks += more
    verdict["values"] = values
    verdict["checks"] = [c.as_dict() for c in checks]
    gaps, pending = spec.get("gaps", {}), spec.get("pending", {})
    failed = [c for c in checks if not c.ok and c.name not in gaps]
    verdict["gaps"] = [
        {"check": c.name, "seen": c.seen, "why": gaps[c.name]} for c in checks if not c.ok and c.name in gaps
    ]
    closed = [c.name for c in checks if c.ok and c.name in gaps]
    problems = [f"{c.name}: {c.seen}" for c in failed]
    if not failed:
        verdict["verdict"] = expect if expect != "pending" else "works (no longer pending: update SPECS)"
    elif expect == "pending" and all(c.name in pending for c in failed):
        verdict["verdict"] = "pending"
        problems = []
        verdict["pending"] = [{"check": c.name, "seen": c.seen, "why": pending[c.name]} for c in failed]
    else:
        verdict["verdict"] = "FAIL"
        if code != want:
            problems.append(f"output: {output[-1500:]}")
    if closed:
        verdict["verdict"] += f" (gap closed: {', '.join(closed)}; update SPECS)"
    if "why" in spec:
        verdict["why"] = spec["why"]
    if expect != "works" or verdict["verdict"] != "works":
        verdict["output_tail"] = output[-600:]
    verdict["ok"] = verdict["verdict"] != "FAIL"
    verdict["problems"] = problems
    return verdict


def rejudge(kept):
    """Judges again the runs `--keep` copied to KEPT/EXAMPLE (after a change of the judge)."""
    for run in sorted(p for p in pathlib.Path(kept).iterdir() if (p / "exit.txt").exists()):
        yield judge_run(
            run.name, (run / "exit.txt").read_text(), (run / "output.txt").read_text(), run / "log", run / "work"
        )


def main():
    runner = runs.Runner(specs=SPECS, default_timeout_s=300.0, fly=fly, fly_inside=fly_inside, rejudge=rejudge)
    known = sorted(d.name for d in EXAMPLES.iterdir() if (d / f"{d.name}.py").exists())
    return runs.main(__doc__.split("\n")[0], known, runner)


if __name__ == "__main__":
    sys.exit(main())
