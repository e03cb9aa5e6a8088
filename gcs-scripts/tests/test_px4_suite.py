"""PX4's MAVSDK integration cases (gcs-scripts/px4_tests, a port of PX4-Autopilot's
test/mavsdk_tests), the fast subset: cases that pass on rotorpilot and take a few seconds of wall
time at --speedup 10, run through gcs-scripts/run_px4_tests.py two at a time, each in its own
network namespace. `run_px4_tests.py` with no argument runs every case."""
import json
import os
import pathlib
import subprocess
import sys

import pytest
from netns import can_unshare

RUNNER = pathlib.Path(__file__).resolve().parents[1] / "run_px4_tests.py"
SUBSET = [
    "Takeoff and Land",
    "Fly square Multicopter Missions including RTL",
    "Land on GPS lost during mission (baro height mode)",
    "Land on GPS lost during mission (GPS height mode)",
    "Continue on mag lost during mission",
    "Parameters download via MAVLink FTP",
    "Parameters upload via MAVLink FTP",
    "Offboard takeoff and land",
    "Offboard position control",
    "Continue on baro stuck during mission (baro height mode)",
    "Follow target - Velocity streaming only",
    "RTL_TYPE=6 time_remaining_s NaN with no rally points",
    "Fly Multicopter Mission with external set-current onto a DO_JUMP item",
    "Goto: reposition on a multicopter flies to and holds at the target",
    "Goto: speed change while flying is applied",
    "Multicopter recovers after missing a waypoint during a home-altitude change",
    "Control Allocation - Terminate on motor failure",
]


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_px4_fast_subset_passes(rotorpilot_bin):
    env = dict(os.environ, ROTORPILOT_BIN=str(rotorpilot_bin))
    run = subprocess.run([sys.executable, str(RUNNER), *SUBSET, "--speedup", "10", "--jobs", "2", "--timeout", "240"],
                         capture_output=True, text=True, env=env, timeout=1200, check=False)
    verdicts = {v["case"]: v for v in (json.loads(line) for line in run.stdout.splitlines() if line.strip())}
    assert sorted(verdicts) == sorted(SUBSET), f"missing verdicts: {run.stdout}\n{run.stderr[-2000:]}"
    for name, verdict in verdicts.items():
        assert verdict["verdict"] == "pass", f"{name}: {verdict}"
    assert run.returncode == 0, run.stderr[-2000:]
