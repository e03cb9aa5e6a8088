"""MAVSDK-Python's own examples, unchanged, flown against the binary (issue: a MAVSDK mission
made the vehicle disarm at 19 m; offboard steps, yaw rates and heading turns were flown wrong;
a repeated REQUEST_MESSAGE went unanswered). The fast subset runs here, concurrently, each in
its own network namespace; `gcs-scripts/run_mavsdk_examples.py` with no argument runs them all."""
import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

RUNNER = pathlib.Path(__file__).resolve().parents[1] / "run_mavsdk_examples.py"

# (example, rotorpilot --speedup): the mission's flight (25 m legs, RTL at 60 m) runs at 4x.
SUBSET = [
    ("firmware_version", "1"),
    ("offboard_position_ned", "1"),
    ("offboard_velocity_ned", "1"),
    ("offboard_velocity_body", "1"),
    ("offboard_position_velocity_ned", "1"),
    ("mission", "4"),
]


def can_unshare():
    return shutil.which("unshare") and subprocess.run(["unshare", "-n", "true"], check=False).returncode == 0


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavsdk_examples_fly_safely_unchanged(rotorpilot_bin):
    env = dict(os.environ, ROTORPILOT_BIN=str(rotorpilot_bin))
    runs = {
        name: subprocess.Popen([sys.executable, str(RUNNER), name, "--speedup", speedup, "--timeout", "200"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        for name, speedup in SUBSET
    }
    verdicts = {}
    for name, proc in runs.items():
        out, err = proc.communicate(timeout=300)
        assert out.strip(), f"{name}: no verdict; {err[-2000:]}"
        verdicts[name] = json.loads(out.strip().splitlines()[-1])
    for name, v in verdicts.items():
        assert v["ok"], f"{name}: {v['problems']}"
        assert v["exit"] == 0 and not v["disarms_in_air"], v
    # What each flight had to do, beyond exiting 0 and never disarming in the air.
    mission = verdicts["mission"]
    assert mission["landed_states"] == ["ON_GROUND", "TAKEOFF", "IN_AIR", "LANDING", "ON_GROUND"], mission
    assert mission["max_height_m"] > 24.0
    landing = verdicts["offboard_position_ned"]
    assert landing["landed_states"] == ["ON_GROUND", "IN_AIR", "ON_GROUND"] and not landing["final_armed"]
    assert landing["touchdown_m_s"] < 1.6, landing
    for name in ("offboard_velocity_ned", "offboard_velocity_body", "offboard_position_velocity_ned"):
        assert verdicts[name]["landed_states"][:2] == ["ON_GROUND", "IN_AIR"], verdicts[name]
