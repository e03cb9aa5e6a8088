"""MAVProxy 1.8.75 in its default (ArduPilot) mode, unchanged, flies `rotorpilot run --autopilot
ardupilot` on its default configuration as its users type it: `mode GUIDED`, `arm throttle`,
`takeoff 10`, `wp load` of a QGC WPL 110 file, `mode AUTO`, `mode RTL`, then the landing and the
disarm. Judged from MAVProxy's console and from the vehicle's tlog (what a ground station was
shown: heartbeats, GLOBAL_POSITION_INT, MISSION_CURRENT, STATUSTEXT). Runs in its own network
namespace, so MAVProxy's fixed port 14550 is used as it is. And MAVProxy's first step, the
parameters downloaded as `@PARAM/param.pck` over MAVLink FTP under the random session number it
picks, as against ArduCopter: every parameter, no fallback to PARAM_REQUEST_LIST."""
import pathlib
import re
import subprocess
import sys

import pytest
from netns import can_unshare
from pymavlink import mavutil

MAVPROXY = pathlib.Path(sys.executable).parent / "mavproxy.py"
# ArduPilot SITL's default home (CMAC, Canberra), so the file reads as ArduPilot users' do.
HOME = "-35.363262,149.165237,584"
# Line 0 is home (ignored by ArduCopter's upload, read back as home); a take-off to 10 m, then
# 20 m north at 10 m and 20 m east of that at 15 m.
MISSION = """QGC WPL 110
0\t1\t0\t16\t0\t0\t0\t0\t-35.3632620\t149.1652370\t584.0\t1
1\t0\t3\t22\t0\t0\t0\t0\t0\t0\t10\t1
2\t0\t3\t16\t0\t0\t0\t0\t-35.3630820\t149.1652370\t10\t1
3\t0\t3\t16\t0\t0\t0\t0\t-35.3630820\t149.1654570\t15\t1
"""
GUIDED, AUTO, RTL = 4, 3, 6


def shown(tlog):
    """What the tlog shows of vehicle 1: (modes in order, armed flags, highest relative altitude
    [m], the last relative altitude [m], mission seqs seen, texts)."""
    log = mavutil.mavlink_connection(str(tlog))
    modes, armed, seqs, texts, top, last = [], [], [], [], 0.0, None
    while (m := log.recv_match(type=["HEARTBEAT", "GLOBAL_POSITION_INT", "MISSION_CURRENT", "STATUSTEXT"])):
        if m.get_srcSystem() != 1:
            continue
        kind = m.get_type()
        if kind == "HEARTBEAT":
            if not modes or modes[-1] != m.custom_mode:
                modes.append(m.custom_mode)
            armed.append(bool(m.base_mode & 128))
        elif kind == "GLOBAL_POSITION_INT":
            last = m.relative_alt / 1000.0
            top = max(top, last)
        elif kind == "MISSION_CURRENT":
            if not seqs or seqs[-1] != m.seq:
                seqs.append(m.seq)
        else:
            texts.append(m.text)
    return modes, armed, top, last, seqs, texts


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavproxy_flies_guided_takeoff_a_wpl_mission_and_rtl(rotorpilot_bin, tmp_path):
    (tmp_path / "mission.txt").write_text(MISSION)
    # Typed at MAVProxy's console, paced as a user would (the vehicle at 8x), with room for a busy
    # machine: the upload is done before AUTO is asked for. The take-off follows the arming within
    # DISARM_DELAY (10 s, 1.25 s of wall time at 8x), as it must against ArduCopter.
    commands = [(6, "mode GUIDED"), (2, "arm throttle"), (1, "takeoff 10"), (3, f"wp load {tmp_path}/mission.txt"),
                (6, "mode AUTO"), (8, "mode RTL"), (10, "")]
    feed = "; ".join(f"sleep {s}; echo '{c}'" for s, c in commands)
    script = f"""
ip link set lo up
{rotorpilot_bin} run --autopilot ardupilot --home={HOME} --speedup 8 --bind-gcs 127.0.0.1:0 \\
    --bind-api 127.0.0.1:0 --log {tmp_path}/vehicle > /dev/null 2>&1 &
vehicle=$!
( {feed} ) | timeout 60 {sys.executable} {MAVPROXY} --master=udpin:127.0.0.1:14550 --state-basedir={tmp_path} 2>&1
kill -INT $vehicle
wait $vehicle
"""
    run = subprocess.run(["unshare", "-n", "bash", "-c", script], capture_output=True, text=True, timeout=120,
                         check=False, cwd=tmp_path)
    out = run.stdout + run.stderr
    for said in ["Detected vehicle 1:1", "Got COMMAND_ACK: DO_SET_MODE: ACCEPTED", "GUIDED> Mode GUIDED",
                 "Got COMMAND_ACK: COMPONENT_ARM_DISARM: ACCEPTED", "AP: Arming motors", "ARMED",
                 "Got COMMAND_ACK: NAV_TAKEOFF: ACCEPTED", "Sent all 4 waypoints", "AP: Flight plan received",
                 "Got MISSION_ACK: TYPE_MISSION: ACCEPTED", "AUTO> Mode AUTO", "waypoint 3", "RTL> Mode RTL",
                 "AP: Disarming motors", "DISARMED"]:
        assert said in out, f"{said!r} missing:\n{out}"
    # FENCE_ENABLE 0 (Copter's default): SYS_STATUS shows the fence present but not enabled.
    assert "fence present" in out and "fence enabled" not in out, out
    modes, armed, top, last, seqs, texts = shown(tmp_path / "vehicle" / "flight.tlog")
    assert [m for m in modes if m in (GUIDED, AUTO, RTL)] == [GUIDED, AUTO, RTL], modes
    assert modes[-1] == RTL, f"landed and disarmed in RTL: {modes}"
    assert 14.0 < top < 16.5, f"climbed to the last waypoint's 15 m: {top}"
    assert last is not None and abs(last) < 0.3 and not armed[-1], (last, armed[-1])
    assert seqs[-3:] == [1, 2, 3], f"items 1 to 3 flown, item 0 is home: {seqs}"
    assert "Flight plan received" in texts


# The vehicle's parameter count, asked on the API link (a PARAM_REQUEST_READ of index 0).
COUNT = """
from pymavlink import mavutil
conn = mavutil.mavlink_connection("udpin:127.0.0.1:14540")
conn.wait_heartbeat(timeout=10)
conn.mav.param_request_read_send(1, 1, b"", 0)
m = conn.recv_match(type="PARAM_VALUE", blocking=True, timeout=10)
print("vehicle param_count", m.param_count)
"""


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavproxy_downloads_the_parameters_over_ftp_under_its_own_session(rotorpilot_bin, tmp_path):
    (tmp_path / "count.py").write_text(COUNT)
    script = f"""
ip link set lo up
{rotorpilot_bin} run --autopilot ardupilot --bind-gcs 127.0.0.1:0 --bind-api 127.0.0.1:0 --no-log > /dev/null 2>&1 &
vehicle=$!
sleep 0.5
timeout 15 {sys.executable} {MAVPROXY} --master=udpin:127.0.0.1:14550 --non-interactive --state-basedir={tmp_path} 2>&1
{sys.executable} {tmp_path}/count.py 2>&1
kill -INT $vehicle
wait $vehicle
"""
    run = subprocess.run(["unshare", "-n", "bash", "-c", script], capture_output=True, text=True, timeout=60,
                         check=False, cwd=tmp_path)
    out = run.stdout + run.stderr
    assert "FTP: request timed out" not in out, out
    received = re.search(r"Received (\d+) parameters \(ftp\)", out)
    assert received, f"no download over FTP:\n{out}"
    count = re.search(r"vehicle param_count (\d+)", out)
    assert count, f"the vehicle's count was not read:\n{out}"
    assert int(received.group(1)) == int(count.group(1)) > 100, (received.group(0), count.group(0))
