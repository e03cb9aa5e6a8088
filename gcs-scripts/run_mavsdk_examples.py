#!/usr/bin/env python3
"""Flies MAVSDK-Python's own examples, unchanged, against rotorpilot and judges each flight.

Each example runs in its own network namespace (`unshare -n`, so the examples' fixed ports,
14540 for MAVLink and 50051 for mavsdk_server's gRPC, never clash), against a fresh
`rotorpilot run --airframe quad_x` that sends its API link to 127.0.0.1:14540 as PX4 SITL does.
The examples are MAVSDK-Python's (BSD-3-Clause, tests/third_party/mavsdk_examples/LICENSE.txt) as
published (examples/ at MAVSDK-Python commit 4fab80e4, 2026-02-11), with mavsdk 3.17.4 and its
bundled mavsdk_server (gcs-scripts/requirements.txt).

Each example is run as a user runs it: `cd examples && python3 NAME.py` (a scratch copy of the
directory, so `mission_import` finds `example-mission.plan` and downloads land there). The table
`SPECS` says what else a user does: the examples that never end by themselves (a loop, a
telemetry printer) are stopped with Ctrl-C (SIGINT to their process group) after a fixed time and
count as running when they were still running then; `shell` gets typed lines on stdin; the FTP
examples talk to a mavsdk_server the user started first (`mavsdk_server -p 50051
udpin://0.0.0.0:14540`), as their `System(mavsdk_server_address=..., port=50051)` expects.

An example that downloads flight logs finds the ones `SPECS` names in the vehicle's `--log`
directory (seeded random bytes, PX4's layout `log/YYYY-MM-DD/HH_MM_SS.ulg`) and must bring each
back byte for byte. Every example flies on `rotorpilot run`'s default configuration (realistic
sensors through the navigation filter, as PX4 SITL): a `SPECS` entry may ask for `--sensors ideal`
only with the reason why (none does).

The flight is judged on what a ground station saw: the telemetry in the vehicle's tlog
(`--log DIR/flight.tlog`, `tlog_judge.py`), never the simulator's truth. Heights are
LOCAL_POSITION_NED.z from the reading before arming (|z| ≤ 0.1 m on the ground then), with
GLOBAL_POSITION_INT.relative_alt beside them; the vehicle must never be disarmed more than 0.5 m
up, must rest within 0.2 m of 0 after every landing, must touch down gently, must end on the
ground (and disarmed) when the example lands; an offboard example's yaw rate must follow each
phase's setpoint (`phases`, from the example's source); after a GPS failure the telemetry must
show the GPS lost; and the vehicle must have done what the example asks (the per-example check
in `SPECS`: modes in HEARTBEAT.custom_mode, heights, messages). Each check reports the values seen.
An example whose refusal is the PX4-like answer (a failure unit without a sensor model, a file
PX4 SITL does not have either) is an "expected refusal": it must fail, and the vehicle must have
answered as expected. A "pending" example needs a vehicle feature not merged yet.
One JSON line per example on stdout (`verdict`: works / expected refusal / pending / FAIL);
exit 1 when any example fails.

usage: run_mavsdk_examples.py [EXAMPLE ...] [--speedup X] [--timeout S] [--keep DIR]
       (no EXAMPLE: every example in tests/third_party/mavsdk_examples/; needs root for unshare -n)
       run_mavsdk_examples.py --rejudge DIR    (the runs kept in DIR judged again, nothing flown)
"""
import json
import pathlib
import random
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time

import example_runs as runs
import tlog_judge as judge
import tlog_yaw as yaw
from rotorpilot_gcs import find_binary
from rotorpilot_gcs.process import checkout_binary
from tlog_judge import (
    ACCEPTED,
    AUTO_LAND,
    AUTO_RTL,
    FOLLOW_TARGET,
    GOTO,
    INJECT_FAILURE,
    OFFBOARD,
    ORBIT,
    POSCTL,
)
from tlog_yaw import Phase

HERE = pathlib.Path(__file__).resolve().parent
EXAMPLES = HERE / "tests" / "third_party" / "mavsdk_examples"
ROOT = HERE.parent


def binary():
    """The rotorpilot binary: ROTORPILOT_BIN, else the checkout's target/release/rotorpilot, else
    rotorpilot on PATH (rotorpilot_gcs.find_binary)."""
    return find_binary(fallback=checkout_binary())


def mavsdk_server():
    """The mavsdk_server bundled with the installed mavsdk package."""
    import importlib.util

    return pathlib.Path(importlib.util.find_spec("mavsdk").origin).parent / "bin" / "mavsdk_server"


# What each example must do besides resting on the ground before arming and never disarming in
# the air. Keys: speedup (rotorpilot --speedup, overriding the command line's), run_for (s; then
# Ctrl-C), stdin (typed lines), server (start mavsdk_server first), expect ("works" | "expected
# refusal" | "pending"), why (the reason of a refusal or wait), sensors and sensors_why
# (rotorpilot --sensors and the reason: only an example that measures something other than the
# flight a user sees may leave the default configuration), lands (ends on the ground), disarms
# (and disarmed), touchdown_max_m_s (instead of TOUCHDOWN_MAX_M_S), phases (the offboard
# setpoints of the example's source, whose yaw is judged), gps_loss (a GPS failure the telemetry
# must show), check (the judged summary and the example's output → a list of problems).
SPECS = {
    "firmware_version": {},
    "takeoff_and_land": {},
    "telemetry_takeoff_and_land": {"lands": True},
    "mission": {"lands": True},
    "offboard_position_ned": {
        "lands": True, "disarms": True,
        # It descends on a position setpoint at z = 0, capped at MPC_Z_VEL_MAX_DN (1.5 m/s), not
        # a landing at MPC_LAND_SPEED.
        "touchdown_max_m_s": 1.6,
        "phases": [Phase("go 5 m up", {"x": 0, "y": 0, "z": -5, "yaw": 0}, 10),
                   Phase("go 5 m north, face east", {"x": 5, "y": 0, "z": -5, "yaw": 90}, 10),
                   Phase("go 10 m east", {"x": 5, "y": 10, "z": -5, "yaw": 90}, 15),
                   Phase("go back north and down to 0, face south", {"x": 0, "y": 10, "z": 0, "yaw": 180}, 10)],
    },
    "offboard_velocity_ned": {
        "phases": [Phase("go up 2 m/s", {"vx": 0, "vy": 0, "vz": -2, "yaw": 0}, 4),
                   Phase("go north 2 m/s, face east", {"vx": 2, "vy": 0, "vz": 0, "yaw": 90}, 4),
                   Phase("go south 2 m/s, face west", {"vx": -2, "vy": 0, "vz": 0, "yaw": 270}, 4),
                   Phase("go west 2 m/s, face east", {"vx": 0, "vy": -2, "vz": 0, "yaw": 90}, 4),
                   Phase("go east 2 m/s", {"vx": 0, "vy": 2, "vz": 0, "yaw": 90}, 4),
                   Phase("turn to face south", {"vx": 0, "vy": 0, "vz": 0, "yaw": 180}, 2),
                   Phase("go down 1 m/s, face north", {"vx": 0, "vy": 0, "vz": 1, "yaw": 0}, 4)],
    },
    "offboard_velocity_body": {
        "phases": [Phase("turn clockwise and climb", {"vx": 0, "vy": 0, "vz": -1, "yaw_rate": 60}, 5),
                   Phase("turn back anti-clockwise", {"vx": 0, "vy": 0, "vz": 0, "yaw_rate": -60}, 5),
                   Phase("wait", {"vx": 0, "vy": 0, "vz": 0, "yaw_rate": 0}, 2),
                   Phase("fly a circle", {"vx": 5, "vy": 0, "vz": 0, "yaw_rate": 30}, 15),
                   Phase("wait", {"vx": 0, "vy": 0, "vz": 0, "yaw_rate": 0}, 5),
                   Phase("fly a circle sideways", {"vx": 0, "vy": -5, "vz": 0, "yaw_rate": 30}, 15),
                   Phase("wait", {"vx": 0, "vy": 0, "vz": 0, "yaw_rate": 0}, 8)],
    },
    "offboard_position_velocity_ned": {
        "phases": [Phase("climb to 10 m at 1 m/s", {"x": 0, "y": 0, "z": -10, "vz": -1, "yaw": 0}, 10),
                   Phase("go north at 1 m/s", {"x": 50, "y": 0, "z": -10, "vx": 1, "vz": 0, "yaw": 0}, 20)],
    },
    "manual_control": {
        "run_for": 35,
        "check": lambda s, out: [p for p in [
            None if POSCTL in s["airborne_modes"] else f"never airborne in POSCTL: {s['airborne_modes']}",
            None if s["max_height_m"] > 1.0 else f"never airborne ({s['max_height_m']} m)",
        ] if p],
    },
    "do_orbit": {
        "check": lambda s, out: [p for p in [
            None if ORBIT in s["airborne_modes"] else f"never in POSCTL.ORBIT: {s['airborne_modes']}",
            None if s["counts"].get("ORBIT_EXECUTION_STATUS", 0) > 100 else "too few ORBIT_EXECUTION_STATUS",
            None if 9.0 < s["max_height_m"] < 11.5 else f"max height {s['max_height_m']} m, not the orbit's 10 m",
            None if 9.0 < s["orbit_radius_m"][0] and s["orbit_radius_m"][1] < 11.0
            else f"{s['orbit_radius_m']} m from the centre on the circle, not 10",
            None if AUTO_RTL in s["airborne_modes"] else "no RTL at the end",
        ] if p],
    },
    "follow_me_example": {
        "check": lambda s, out: [p for p in [
            None if FOLLOW_TARGET in s["airborne_modes"] else f"never in AUTO.FOLLOW_TARGET: {s['airborne_modes']}",
            None if s["counts"].get("FOLLOW_TARGET", 0) >= 3 else "fewer than 3 FOLLOW_TARGET received",
            # The example's target is 8 m below home with FLW_TGT_HT 8 m: PX4 holds 1 m above home
            None if s.get("min_follow_height_m", 0.0) > 0.6 else f"followed down to {s.get('min_follow_height_m')} m",
            None if AUTO_LAND in s["modes"] else "no landing at the end",
        ] if p],
    },
    "goto": {
        "run_for": 70,
        # goto_location switches to Hold, then sends DO_REPOSITION with the mode-change flag: PX4
        # flies it in its Goto mode (AUTO sub mode 21) and stays there, holding at the target.
        "check": lambda s, out: [p for p in [
            None if GOTO in s["airborne_modes"] else f"never airborne in Goto: {s['airborne_modes']}",
            None if 19.0 < s["final_height_m"] < 21.0 else f"final height {s['final_height_m']} m, not the 20 m asked",
            None if s["final_target_m"] < 3.0
            else f"not at the target: {s['start_target_m']} m → {s['final_target_m']} m",
        ] if p],
        "target": (47.397606, 8.543060),
    },
    "offboard_attitude": {
        "check": lambda s, out: [p for p in [
            None if OFFBOARD in s["airborne_modes"] else f"never airborne in OFFBOARD: {s['airborne_modes']}",
            None if s["max_height_m"] > 1.0 else f"never airborne ({s['max_height_m']} m)",
            None if AUTO_LAND in s["modes"] else "no landing at the end",
        ] if p],
    },
    "mission_raw": {
        "check": lambda s, out: [] if (0, 0) in s["mission_acks"]
        else [f"no MISSION_ACK ACCEPTED: {s['mission_acks']}"],
    },
    "mission_import": {
        "check": lambda s, out: [] if {(0, 0), (2, 0)} <= set(s["mission_acks"])
        else [f"mission and rally points not both accepted: {s['mission_acks']}"],
    },
    "geofence": {
        "check": lambda s, out: [] if (1, 0) in s["mission_acks"] else [f"fence not accepted: {s['mission_acks']}"],
    },
    "telemetry": {
        "run_for": 15,
        "check": lambda s, out: [f"no {w!r} printed" for w in ("Battery:", "GPS info:", "In air: False",
                                                               "Position: [") if w not in out],
    },
    "telemetry_flight_mode": {
        "run_for": 10,
        "check": lambda s, out: [] if "FlightMode: HOLD" in out else ["no 'FlightMode: HOLD' printed"],
    },
    "all_params": {
        "check": lambda s, out: [] if len(re.findall(r"^[A-Z][A-Z0-9_]*: ", out, re.M)) == s["param_count"] > 80
        else [f"printed {len(re.findall(r'^[A-Z][A-Z0-9_]*: ', out, re.M))} of {s['param_count']} parameters"],
    },
    "shell": {
        "stdin": "help\nver all\n",
        "check": lambda s, out: [] if "Connected to drone" in out else ["never connected"],
    },
    "ftp_list_dir": {
        "server": True,
        "check": lambda s, out: [] if "directory list" in out and "fs" in out else ["no directory listed"],
    },
    "ftp_download_file": {
        "server": True,
        "expect": "expected refusal",
        "why": "it asks for /etc/extras/px4_io-v2_default.bin, a Pixhawk's IO firmware that PX4 SITL "
               "does not have either: the vehicle answers FTP NAK FileNotFound",
        "check": lambda s, out: [] if "FILE_DOES_NOT_EXIST" in out else ["no 'file does not exist' error"],
    },
    "logfile_download": {
        # Two logs in the vehicle's log directory before it starts, downloaded by the example to
        # ./log-<date>.ulog and compared with them byte for byte (a size not a multiple of 90
        # bytes, and a log of a few bytes).
        "logs": {"2026-01-01/10_00_00.ulg": 20001, "2026-01-02/11_30_00.ulg": 3},
        "check": lambda s, out: [] if "Log 1 from 2026-01-02T11:30:00Z" in out else ["second log not listed"],
    },
    "failure_injection": {
        # The GPS goes off at 20 m: the filter dead-reckons for EKF2_NOAID_TOUT (5 s), then the
        # position is invalid and the vehicle descends level (shown as AUTO.LAND), lands and
        # disarms. The example waits 20 s after the failure, then exits: flown at --speedup 5 so
        # that its wait covers the descent from 20 m.
        "speedup": "5", "lands": True, "disarms": True, "gps_loss": True,
        "check": lambda s, out: [p for p in [
            None if (INJECT_FAILURE, ACCEPTED) in s["command_acks"] else f"GPS off not accepted: {s['command_acks']}",
            None if "GPS lost: dead reckoning" in s["statustexts"] else f"no GPS loss announced: {s['statustexts']}",
            None if "No position estimate: descending" in s["statustexts"] else "no descent announced",
            None if AUTO_LAND in s["modes"] else "never in AUTO.LAND",
            None if s["max_height_m"] > 15.0 else f"did not climb towards 20 m ({s['max_height_m']} m)",
        ] if p],
    },
    "calibration": {
        "expect": "expected refusal",
        "why": "gyro calibration completes; accelerometer calibration needs the vehicle turned onto "
               "its six sides, which the simulation cannot do: '[cal] calibration failed' as PX4 "
               "reports a calibration it cannot finish",
        "check": lambda s, out: [p for p in [
            None if "[cal] calibration done: gyro" in s["statustexts"] else "gyro calibration not done",
            None if any(t.startswith("[cal] calibration failed") for t in s["statustexts"]) else "no failure reason",
        ] if p],
    },
}


def fly_inside(example, spec, log_dir, work_dir, speedup, timeout_s):
    """In the namespace: starts the vehicle, runs the example; the example's exit code and output
    (code "running" when it was stopped with Ctrl-C while still running)."""
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    argv = [str(binary()), "run", "--airframe", "quad_x", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0",
            "--log", str(log_dir), "--speedup", str(speedup)]
    if "sensors" in spec:  # the default configuration unless the example says why not
        assert spec.get("sensors_why"), f"{example}: SPECS gives sensors without sensors_why"
        argv += ["--sensors", spec["sensors"]]
    vehicle = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    server = None
    try:
        ready = json.loads(vehicle.stdout.readline())
        assert ready.get("event") == "ready", ready
        if spec.get("server"):
            # Started where the example runs: the server writes downloads relative to its own cwd.
            server = subprocess.Popen([str(mavsdk_server()), "-p", "50051", "udpin://0.0.0.0:14540"],
                                      cwd=work_dir, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        run = subprocess.Popen([sys.executable, f"{example}.py"], cwd=work_dir, stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               start_new_session=True)
        lines = []
        reader = threading.Thread(target=lambda: lines.extend(iter(run.stdout.readline, "")), daemon=True)
        reader.start()
        started = time.monotonic()
        stdin = spec.get("stdin")
        if stdin is not None:
            # Typed a line at a time, after the example has had time to connect.
            time.sleep(5)
            for line in stdin.splitlines(keepends=True):
                try:
                    run.stdin.write(line)
                    run.stdin.flush()
                except (BrokenPipeError, ValueError):
                    break
                time.sleep(1)
        limit = spec.get("run_for") or timeout_s
        code = runs.watch(run, lines, started, limit, over="running" if spec.get("run_for") else 124)
        reader.join(timeout=5)
        output = "".join(lines)
    finally:
        if server is not None:
            runs.stop(server, 5)
        runs.stop(vehicle)
    return code, output


def log_bytes(logs):
    """The flight logs `logs` ({name under DIR/log: size}) as seeded pseudo-random bytes, by name."""
    return {name: random.Random(name).randbytes(size) for name, size in logs.items()}


def place_logs(log_dir, logs):
    """Writes the flight logs `logs` ({name under DIR/log: size}) into the vehicle's `--log` DIR;
    their bytes by name."""
    placed = log_bytes(logs)
    for name, data in placed.items():
        path = pathlib.Path(log_dir, "log", name)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    return placed


def downloads_differ(work_dir, placed):
    """Problems with the example's downloads: `log-<date>.ulog` (MAVSDK's ISO date with ':' as
    '-') must hold each placed log's bytes."""
    problems = []
    for name, data in placed.items():
        day, clock = name[:-len(".ulg")].split("/")
        got = pathlib.Path(work_dir, f"log-{day}T{clock.replace('_', '-')}Z.ulog")
        if not got.exists():
            problems.append(f"{name} not downloaded to {got.name}")
        elif got.read_bytes() != data:
            problems.append(f"{got.name}: {got.stat().st_size} bytes differ from {name}'s {len(data)}")
    return problems


def fly(example, speedup, timeout_s, keep):
    """Runs one example in a new network namespace; its verdict as a dict."""
    spec = SPECS.get(example, {})
    speedup = spec.get("speedup", speedup)
    scratch = pathlib.Path(tempfile.mkdtemp(prefix=f"rp-{example}-"))
    log_dir, work_dir = scratch / "log", scratch / "examples"
    shutil.copytree(EXAMPLES, work_dir)
    placed = place_logs(log_dir, spec.get("logs", {}))
    inner = subprocess.run(
        ["unshare", "-n", sys.executable, __file__, "--inside", example, "--log-dir", str(log_dir),
         "--work-dir", str(work_dir), "--speedup", str(speedup), "--timeout", str(timeout_s)],
        capture_output=True, text=True, timeout=timeout_s + 60, check=False)
    lines = inner.stdout.splitlines()
    code = lines[0] if lines and lines[0].startswith("exit ") else f"exit runner {inner.returncode}"
    output = "\n".join(lines[1:]) + inner.stderr
    verdict = judge_run(example, code[5:], output, log_dir, work_dir, placed)
    if keep:
        shutil.copytree(scratch, pathlib.Path(keep) / example, dirs_exist_ok=True)
        pathlib.Path(keep, example, "output.txt").write_text(output)
        pathlib.Path(keep, example, "exit.txt").write_text(verdict["exit"])
    shutil.rmtree(scratch, ignore_errors=True)
    return verdict


def judge_run(example, code, output, log_dir, work_dir, placed):
    """The verdict of one run from its exit `code`, its `output`, the vehicle's tlog in `log_dir`
    and what the example left in `work_dir` (`placed`: the logs it had to download)."""
    spec = SPECS.get(example, {})
    verdict = {"example": example, "exit": code, "expect": spec.get("expect", "works")}
    tlog = pathlib.Path(log_dir, "flight.tlog")
    problems = [] if tlog.exists() else ["no flight log"]
    if tlog.exists():
        telemetry = judge.Telemetry(tlog)
        summary = judge.summarize(telemetry, spec.get("target"))
        verdict.update({k: v for k, v in summary.items() if k not in ("counts", "statustexts", "command_acks")})
        checks = judge.ground_checks(summary, spec.get("lands", False), spec.get("disarms", False),
                                     spec.get("touchdown_max_m_s", judge.TOUCHDOWN_MAX_M_S))
        checks += yaw.yaw_checks(telemetry, spec.get("phases", ()))
        if spec.get("gps_loss"):
            checks += judge.gps_loss_checks(telemetry)
        verdict["checks"] = [c.as_dict() for c in checks]
        problems += [f"{c.name}: {c.seen}" for c in checks if not c.ok]
        if "check" in spec:
            problems += spec["check"](summary, output)
        problems += downloads_differ(work_dir, placed)
    ran = verdict["exit"] == ("running" if spec.get("run_for") else "0")
    expect = verdict["expect"]
    if expect == "works":
        if not ran:
            problems.insert(0, f"exit {verdict['exit']}: {output[-1500:]}")
        verdict["verdict"] = "works" if not problems else "FAIL"
    elif expect == "expected refusal":
        if ran:
            problems.insert(0, "it succeeded: the refusal it expects is gone, update SPECS")
        verdict["verdict"] = "expected refusal" if not problems else "FAIL"
        verdict["why"] = spec["why"]
    else:
        if ran:
            verdict["verdict"] = "works (no longer pending: update SPECS)"
        else:
            verdict["verdict"] = "pending" if not problems else "FAIL"
        verdict["why"] = spec["why"]
        if not ran:
            verdict["pending_output"] = output[-600:]
    verdict["ok"] = verdict["verdict"] != "FAIL"
    verdict["problems"] = problems
    return verdict


def rejudge(kept):
    """Judges again the runs `--keep` copied to KEPT/EXAMPLE (after a change of the judge)."""
    for run in sorted(p for p in pathlib.Path(kept).iterdir() if (p / "exit.txt").exists()):
        placed = log_bytes(SPECS.get(run.name, {}).get("logs", {}))
        yield judge_run(run.name, (run / "exit.txt").read_text(), (run / "output.txt").read_text(), run / "log",
                        run / "examples", placed)


def main():
    runner = runs.Runner(specs=SPECS, default_timeout_s=240.0, fly=fly, fly_inside=fly_inside, rejudge=rejudge)
    return runs.main(__doc__.split("\n")[0], sorted(f.stem for f in EXAMPLES.glob("*.py")), runner)


if __name__ == "__main__":
    sys.exit(main())
