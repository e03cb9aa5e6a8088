"""DroneKit-Python's own examples, unchanged, flown against the binary's ArduCopter personality
(`rotorpilot run --autopilot ardupilot`, home at ArduPilot SITL's CMAC, default configuration:
realistic sensors) and judged on what a ground station sees in the vehicle's tlog. The fast subset
runs here, at most two at once, each in its own network namespace (the examples' fixed
`udpin:127.0.0.1:14550`); `gcs-scripts/run_dronekit_examples.py` with no argument runs them all,
the expected refusal and the pending examples included (docs/gcs_scripts.md §6)."""

import json
import os
import pathlib
import subprocess
import sys
import time

import pytest
from netns import can_unshare

RUNNER = pathlib.Path(__file__).resolve().parents[1] / "run_dronekit_examples.py"

# (example, rotorpilot --speedup), the longest first. simple_goto's two legs are 30 s of the
# example's wall clock each whatever the speedup; at 4x the legs reach both points and the RTL
# lands within about 20 s of its end. The others finish within seconds of their own timing
# (create_attribute prints RAW_IMU for 5 s, performance_test times COMMAND_ACKs for 30 s).
# CONCURRENT at most (two cores shared with other work; the examples' timing is wall time).
CONCURRENT = int(os.environ.get("DRONEKIT_EXAMPLES_CONCURRENT", "2"))
SUBSET = [
    ("simple_goto", "4"),
    ("performance_test", "1"),
    ("create_attribute", "1"),
    ("channel_overrides", "1"),
]
GUIDED, RTL = 4, 6  # ArduCopter's HEARTBEAT custom_mode


def check(verdict, name):
    """The verdict's check called `name`."""
    return next(c for c in verdict["checks"] if c["check"] == name)


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_dronekit_examples_fly_unchanged(rotorpilot_bin):
    env = dict(os.environ, ROTORPILOT_BIN=str(rotorpilot_bin))
    verdicts, waiting, running = {}, list(SUBSET), {}
    while waiting or running:
        while waiting and len(running) < CONCURRENT:
            name, speedup = waiting.pop(0)
            running[name] = subprocess.Popen(
                [sys.executable, str(RUNNER), name, "--speedup", speedup, "--timeout", "200"],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env=env,
            )
        time.sleep(0.5)
        for name, proc in list(running.items()):
            if proc.poll() is None:
                continue
            out, err = proc.communicate()
            del running[name]
            assert out.strip(), f"{name}: no verdict; {err[-2000:]}"
            verdicts[name] = json.loads(out.strip().splitlines()[-1])
    # Every failing example at once, each problem with the values seen.
    failed = {name: v["problems"] for name, v in verdicts.items() if not v["verdict"].startswith("works")}
    assert not failed, json.dumps(failed, indent=1, ensure_ascii=False)
    for name, v in verdicts.items():
        assert v["exit"] == "0" and not v["disarms_in_air"], v
    # simple_goto: on the ground before arming, GUIDED take-off to 10 m, both points of the source
    # approached at the speeds asked (3 m/s, then 10 m/s), RTL home, landed gently and disarmed.
    goto = verdicts["simple_goto"]
    assert goto["rest_at"] == "before the first arming" and abs(goto["rest_z_m"]) <= 0.1, goto["rest_z_m"]
    assert GUIDED in goto["airborne_modes"] and RTL in goto["airborne_modes"], goto["airborne_modes"]
    values = goto["values"]
    assert 9.5 <= values["takeoff_alt_m"] <= 11.0, values
    for leg in ("leg 1", "leg 2"):
        assert check(goto, f"{leg} approached")["ok"], goto["checks"]
    assert values["leg1"]["closest_m"] < values["leg1"]["start_m"] - 50.0, values["leg1"]
    assert values["leg2"]["closest_m"] < values["leg2"]["start_m"] - 50.0, values["leg2"]
    assert values["home_at_rtl_m"] > 50.0 and values["home_final_m"] <= 3.0, values
    assert goto["landed_states"][-1] == "ON_GROUND" and not goto["final_armed"], goto
    landing = goto["landings"][-1]
    assert landing["touchdown_m_s"] <= 1.0 and abs(landing["rest_height_m"]) <= 0.2, landing
    assert landing["disarmed_after_s"] is not None, landing
    # performance_test: every DO_SET_ROI sent on a COMMAND_ACK answered, round trips printed.
    perf = verdicts["performance_test"]["values"]
    assert perf["roi_sent"] >= 100 and perf["roi_acks"] >= perf["roi_sent"] - 1, perf
    assert perf["max_interval_s"] < 1.0, perf
    # create_attribute: RAW_IMU through the custom attribute, about -1 g on z at rest, and the
    # World Magnetic Model's field at CMAC pointing up (-531 mgauss on z, level).
    imu = verdicts["create_attribute"]["values"]
    assert imu["raw_imu_lines"] >= 15 and -1100 <= imu["zacc_mg"] <= -900, imu
    assert -580 <= imu["zmag_mgauss"] <= -480, imu
    # channel_overrides: the example ends cleanly and its first override reaches the vehicle.
    assert verdicts["channel_overrides"]["values"]["overrides_received"] >= 1, verdicts["channel_overrides"]
