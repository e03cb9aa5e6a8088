#!/usr/bin/env python3
"""Flies MAVSDK-Python's own examples, unchanged, against rotorpilot and judges each flight.

Each example runs in its own network namespace (`unshare -n`, so the examples' fixed ports,
14540 for MAVLink and 50051 for mavsdk_server's gRPC, never clash), against a fresh
`rotorpilot run --airframe quad_x` that sends its API link to 127.0.0.1:14540 as PX4 SITL does.
The examples are MAVSDK-Python's (BSD-3-Clause, tests/third_party/mavsdk_examples/LICENSE.txt) as published,
with mavsdk 3.17.4 and its bundled mavsdk_server (gcs-scripts/requirements.txt).

The flight log (`--log`) is then read back: the example must exit 0, the vehicle must never be
disarmed more than 0.5 m above the ground, and must end on the ground when the example lands
(and disarmed, for an example that waits COM_DISARM_LAND after touch-down). One JSON line per example on stdout; exit 1 when any example fails.

usage: run_mavsdk_examples.py [EXAMPLE ...] [--speedup X] [--timeout S] [--keep DIR]
       (no EXAMPLE: every example in tests/third_party/mavsdk_examples/; needs root for unshare -n)
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
EXAMPLES = HERE / "tests" / "third_party" / "mavsdk_examples"
ROOT = HERE.parent
# Examples that end once the vehicle is on the ground (they stop watching at touch-down).
LANDING = {"mission", "offboard_position_ned", "telemetry_takeoff_and_land"}
# Examples that wait long enough after touch-down for COM_DISARM_LAND (2 s) to disarm.
DISARMING = {"offboard_position_ned"}
# A disarm above this height [m] is a vehicle dropped from the sky.
DISARM_HEIGHT_MAX_M = 0.5


def binary():
    """The rotorpilot binary: ROTORPILOT_BIN or target/release/rotorpilot."""
    return pathlib.Path(os.environ.get("ROTORPILOT_BIN", ROOT / "target" / "release" / "rotorpilot"))


def fly_inside(example, log_dir, speedup, timeout_s):
    """In the namespace: starts the vehicle, runs the example; the example's exit code and output."""
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    vehicle = subprocess.Popen(
        [str(binary()), "run", "--airframe", "quad_x", "--bind-gcs", "127.0.0.1:0", "--bind-api",
         "127.0.0.1:0", "--log", str(log_dir), "--speedup", str(speedup)],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        ready = json.loads(vehicle.stdout.readline())
        assert ready.get("event") == "ready", ready
        try:
            run = subprocess.run([sys.executable, str(EXAMPLES / f"{example}.py")], capture_output=True,
                                 text=True, timeout=timeout_s, check=False)
            code, output = run.returncode, run.stdout + run.stderr
        except subprocess.TimeoutExpired as e:
            code, output = 124, f"timed out after {timeout_s} s\n{e.stdout or ''}{e.stderr or ''}"
    finally:
        vehicle.send_signal(2)
        try:
            vehicle.wait(timeout=10)
        except subprocess.TimeoutExpired:
            vehicle.kill()
    return code, output


def judge(tlog):
    """What the vehicle did, from the tlog: heights, disarms in the air, final state."""
    from pymavlink import mavutil

    log = mavutil.mavlink_connection(str(tlog))
    height, armed, landed = 0.0, False, None
    summary = {"max_height_m": 0.0, "disarms_in_air": [], "landed_states": [], "touchdown_m_s": 0.0}
    while True:
        m = log.recv_match(type=["GLOBAL_POSITION_INT", "HEARTBEAT", "EXTENDED_SYS_STATE"])
        if m is None:
            break
        if m.get_srcSystem() != 1 or m.get_srcComponent() != 1:
            continue
        kind = m.get_type()
        if kind == "GLOBAL_POSITION_INT":
            height = m.relative_alt / 1000.0 - 0.1
            summary["max_height_m"] = max(summary["max_height_m"], height)
            if height < 0.3 and armed:
                summary["touchdown_m_s"] = max(summary["touchdown_m_s"], m.vz / 100.0)
        elif kind == "HEARTBEAT":
            now_armed = bool(m.base_mode & mavutil.mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
            if armed and not now_armed and height > DISARM_HEIGHT_MAX_M:
                summary["disarms_in_air"].append(round(height, 2))
            armed = now_armed
        elif kind == "EXTENDED_SYS_STATE" and m.landed_state != landed:
            landed = m.landed_state
            summary["landed_states"].append(mavutil.mavlink.enums["MAV_LANDED_STATE"][landed].name[17:])
    summary["final_armed"] = armed
    summary["final_height_m"] = round(height, 2)
    return summary


def fly(example, speedup, timeout_s, keep):
    """Runs one example in a new network namespace; its verdict as a dict."""
    log_dir = pathlib.Path(tempfile.mkdtemp(prefix=f"rp-{example}-"))
    inner = subprocess.run(
        ["unshare", "-n", sys.executable, __file__, "--inside", example, "--log-dir", str(log_dir),
         "--speedup", str(speedup), "--timeout", str(timeout_s)],
        capture_output=True, text=True, timeout=timeout_s + 60, check=False)
    verdict = {"example": example, "exit": inner.returncode}
    tlog = log_dir / "flight.tlog"
    verdict.update(judge(tlog) if tlog.exists() else {"error": "no flight log"})
    problems = []
    if inner.returncode != 0:
        problems.append(f"exit {inner.returncode}: {inner.stdout[-800:]}{inner.stderr[-800:]}")
    if verdict.get("disarms_in_air"):
        problems.append(f"disarmed in the air at {verdict['disarms_in_air']} m")
    on_ground = verdict.get("landed_states", [None])[-1] == "ON_GROUND" and verdict.get("final_height_m", 9) < 0.3
    if example in LANDING and not on_ground:
        problems.append("did not end on the ground")
    if example in DISARMING and verdict.get("final_armed", True):
        problems.append("did not disarm after landing")
    verdict["ok"] = not problems
    verdict["problems"] = problems
    if keep:
        shutil.copytree(log_dir, pathlib.Path(keep) / example, dirs_exist_ok=True)
    shutil.rmtree(log_dir, ignore_errors=True)
    return verdict


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("examples", nargs="*", help="example names (default: all)")
    p.add_argument("--speedup", default="1", help="rotorpilot --speedup (default 1)")
    p.add_argument("--timeout", type=float, default=240.0, help="seconds per example (default 240)")
    p.add_argument("--keep", help="copy each flight's logs to KEEP/EXAMPLE")
    p.add_argument("--inside", help=argparse.SUPPRESS)
    p.add_argument("--log-dir", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.inside:
        code, output = fly_inside(args.inside, args.log_dir, args.speedup, args.timeout)
        sys.stdout.write(output)
        return code
    names = args.examples or sorted(f.stem for f in EXAMPLES.glob("*.py"))
    unknown = [n for n in names if not (EXAMPLES / f"{n}.py").exists()]
    if unknown:
        p.error(f"unknown example(s) {unknown}; known: {sorted(f.stem for f in EXAMPLES.glob('*.py'))}")
    failed = 0
    for name in names:
        verdict = fly(name, args.speedup, args.timeout, args.keep)
        print(json.dumps(verdict), flush=True)
        failed += not verdict["ok"]
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
