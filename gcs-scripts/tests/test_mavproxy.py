"""MAVProxy 1.8.75, unchanged, connects to the binary as its users start it
(`mavproxy.py --master=udpin:127.0.0.1:14550`): it finds the vehicle, downloads every parameter,
reads the geofence as present and enabled and prints no false "fence breach" (it reads a clear
MAV_SYS_STATUS_GEOFENCE health bit as a breach); its `fence` and `rally` commands (load, list,
add, clear) work over the mission protocol with mission_type 1 and 2; `log list` ends with "No
logs". Runs in its own network namespace, so the fixed port 14550 is used as it is."""
import pathlib
import re
import subprocess
import sys

import pytest
from netns import can_unshare

MAVPROXY = pathlib.Path(sys.executable).parent / "mavproxy.py"
# The console modules MAVProxy loads here (its map, console GUI and camera modules need the GUI
# dependencies that requirements-nodeps.txt leaves out).
MODULES = "fence,link,param,mode,arm,signing,misc"


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


# MAVProxy's old fence file: the return point, then the polygon's vertices, then the first vertex
# again to close it (±15 m about home); its `fence load` sends it as FENCE_RETURN_POINT and four
# NAV_FENCE_POLYGON_VERTEX_INCLUSION items over the mission protocol with mission_type 1.
FENCE_FILE = """47.397742 8.545594
47.3978770 8.5453940
47.3976070 8.5453940
47.3976070 8.5457940
47.3978770 8.5457940
47.3978770 8.5453940
"""
RALLY_FILE = """QGC WPL 110
0\t0\t3\t5100\t0\t0\t0\t0\t47.3980120\t8.5455940\t10\t0
1\t0\t3\t5100\t0\t0\t0\t0\t47.3971960\t8.5455940\t10\t0
"""


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavproxy_fence_and_rally_commands_work_unchanged(rotorpilot_bin, tmp_path):
    (tmp_path / "fence.txt").write_text(FENCE_FILE)
    (tmp_path / "rally.txt").write_text(RALLY_FILE)
    # Typed commands, paced as a user would (MAVProxy reads them from its console).
    commands = [(6, f"fence load {tmp_path}/fence.txt"), (3, f"rally load {tmp_path}/rally.txt"),
                (3, "fence list"), (2, "rally list"), (2, "click 47.3975 8.5456"), (0, "rally add 15"),
                (3, "rally list"), (2, "fence clear"), (2, "fence list"), (2, "")]
    feed = "; ".join(f"sleep {s}; echo '{c}'" for s, c in commands)
    script = f"""
ip link set lo up
{rotorpilot_bin} run --airframe quad_x --bind-gcs 127.0.0.1:0 --bind-api 127.0.0.1:0 > /dev/null 2>&1 &
vehicle=$!
( {feed} ) | timeout 45 {sys.executable} {MAVPROXY} --master=udpin:127.0.0.1:14550 \\
    --default-modules=fence,rally,link,param,misc --state-basedir={tmp_path} 2>&1
kill -INT $vehicle
wait $vehicle
"""
    run = subprocess.run(["unshare", "-n", "bash", "-c", script], capture_output=True, text=True, timeout=90,
                         check=False, cwd=tmp_path)
    out = run.stdout + run.stderr
    assert "Got MISSION_ACK: TYPE_FENCE: ACCEPTED" in out, out
    assert "Got MISSION_ACK: TYPE_RALLY: ACCEPTED" in out, out
    listed = re.findall(r"^(50\d\d) (\d) ([-\d.]+) ([-\d.]+) [-\d.]+ p1=([-\d.]+)", out, re.MULTILINE)
    fence = [row for row in listed if row[0] in ("5000", "5001")]
    assert [row[0] for row in fence] == ["5000", "5001", "5001", "5001", "5001"], out
    assert all(row[4] == "4.0" for row in fence[1:]), "vertex count in param1"
    assert "Requesting 3 rally items" in out, "the added rally point went up: " + out
    assert "47.3975000000 8.5456000000 15.000000" in out, out
    assert "Requesting 0 fence items" in out, "the fence was cleared: " + out


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
