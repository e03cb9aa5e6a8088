"""MAVProxy 1.8.75, unchanged, connects to the binary as its users start it
(`mavproxy.py --master=udpin:127.0.0.1:14550`): it finds the vehicle, downloads every parameter,
reads the geofence as present and enabled and prints no false "fence breach" (it reads a clear
MAV_SYS_STATUS_GEOFENCE health bit as a breach); `log list` ends with "No logs". Runs in its own
network namespace, so the fixed port 14550 is used as it is."""
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

MAVPROXY = pathlib.Path(sys.executable).parent / "mavproxy.py"
# The console modules MAVProxy loads here (its map, console GUI and camera modules need the GUI
# dependencies that requirements-nodeps.txt leaves out).
MODULES = "fence,link,param,mode,arm,signing,misc"


def can_unshare():
    return shutil.which("unshare") and subprocess.run(["unshare", "-n", "true"], check=False).returncode == 0


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavproxy_connects_without_a_false_fence_breach(rotorpilot_bin, tmp_path):
    script = f"""
ip link set lo up
{rotorpilot_bin} run --airframe quad_x --bind-gcs 127.0.0.1:0 --bind-api 127.0.0.1:0 > /dev/null 2>&1 &
vehicle=$!
timeout 12 {sys.executable} {MAVPROXY} --master=udpin:127.0.0.1:14550 --non-interactive \\
    --default-modules={MODULES} --state-basedir={tmp_path} 2>&1
kill -INT $vehicle
wait $vehicle
"""
    run = subprocess.run(["unshare", "-n", "bash", "-c", script], capture_output=True, text=True, timeout=60,
                         check=False, cwd=tmp_path)
    out = run.stdout + run.stderr
    assert "Detected vehicle 1:1" in out, out
    assert "fence present" in out and "fence enabled" in out, out
    assert "fence breach" not in out.lower(), out
    received = re.search(r"Received (\d+) parameters", out)
    assert received is not None and int(received.group(1)) >= 80, out


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavproxy_log_list_says_no_logs(rotorpilot_bin, tmp_path):
    """`log list` typed at MAVProxy's prompt once the vehicle is detected: the vehicle answers
    LOG_REQUEST_LIST with PX4's empty list (LOG_ENTRY num_logs 0) and MAVProxy prints "No logs"
    instead of waiting for entries."""
    script = f"""
ip link set lo up
{rotorpilot_bin} run --airframe quad_x --bind-gcs 127.0.0.1:0 --bind-api 127.0.0.1:0 > /dev/null 2>&1 &
vehicle=$!
(sleep 6; echo "log list"; sleep 4; echo "exit") | timeout 20 {sys.executable} {MAVPROXY} \\
    --master=udpin:127.0.0.1:14550 --default-modules=link,param,log --state-basedir={tmp_path} 2>&1
kill -INT $vehicle
wait $vehicle
"""
    run = subprocess.run(["unshare", "-n", "bash", "-c", script], capture_output=True, text=True, timeout=60,
                         check=False, cwd=tmp_path)
    out = run.stdout + run.stderr
    assert "Detected vehicle 1:1" in out and "Requesting log list" in out, out
    assert "No logs" in out, out
