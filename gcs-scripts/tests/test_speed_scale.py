"""Speed-up and many vehicles: `rotorpilot run --speedup` and `--count`, the swarm script, the
same flight at 1× and 20×, and `rotorpilot bench --quick --json`. Ports are all ephemeral."""
import json
import os
import pathlib
import subprocess
import sys
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "gcs-scripts"
NAN = float("nan")
ACCEPTED = 0


class Process:
    """`rotorpilot run ARGS` on ephemeral ports; the ready line parsed."""

    def __init__(self, binary, *args):
        self.proc = subprocess.Popen(
            [str(binary), "run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0", "--gcs", "127.0.0.1:9",
             "--api", "127.0.0.1:9", "--duration", "120", *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = json.loads(self.proc.stdout.readline())

    def connect(self, index=0):
        """A pymavlink connection to vehicle `index`'s GCS link (udpout to its bind port)."""
        conn = mavutil.mavlink_connection(f"udpout:{self.ready['vehicles'][index]['gcs_bind']}",
                                          source_system=255, source_component=190)
        conn.mav.heartbeat_send(6, 8, 0, 0, 0)
        return conn

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
        self.proc.wait(timeout=10)
        return self.proc.stderr.read()


def command(conn, cmd, *params, sysid=1):
    p = list(params) + [NAN] * (7 - len(params))
    conn.mav.command_long_send(sysid, 1, cmd, 0, *p)
    deadline = time.monotonic() + 2
    while time.monotonic() < deadline:
        ack = conn.recv_match(type="COMMAND_ACK", blocking=True, timeout=0.2)
        if ack is not None and ack.command == cmd:
            return ack.result
    return None


def test_count_gives_separate_vehicles_on_a_grid(rotorpilot_bin):
    ap = Process(rotorpilot_bin, "--count", "4", "--spacing", "5", "--sysid", "11")
    try:
        vehicles = ap.ready["vehicles"]
        assert [v["sysid"] for v in vehicles] == [11, 12, 13, 14]
        assert len({v["gcs_bind"] for v in vehicles} | {v["api_bind"] for v in vehicles}) == 8
        assert [v["api"] for v in vehicles] == ["127.0.0.1:9", "127.0.0.1:10", "127.0.0.1:11", "127.0.0.1:12"]
        homes = []
        for i in range(4):
            conn = ap.connect(i)
            hb = conn.recv_match(type="HEARTBEAT", blocking=True, timeout=3)
            assert hb is not None and hb.get_srcSystem() == 11 + i
            command(conn, 512, 242, sysid=11 + i)
            home = conn.recv_match(type="HOME_POSITION", blocking=True, timeout=3)
            homes.append((home.latitude, home.longitude))
            conn.close()
        metre = 1e7 / (6371000 * 3.141592653589793 / 180)
        # A 2 × 2 grid, 5 m apart: rows north, columns east.
        assert abs((homes[2][0] - homes[0][0]) / metre - 5) < 0.01 and homes[1][0] == homes[0][0]
        assert homes[1][1] > homes[0][1] and homes[3][1] == homes[1][1]
    finally:
        ap.close()


def test_speedup_runs_every_timer_in_simulated_time(rotorpilot_bin):
    ap = Process(rotorpilot_bin, "--speedup", "20")
    try:
        conn = ap.connect()
        first = conn.recv_match(type="ATTITUDE", blocking=True, timeout=3)
        # Read all along: at 20× the streams fill a default socket buffer in about half a second,
        # and the kernel would drop the newest messages.
        last = None
        end = time.monotonic() + 1.0
        while time.monotonic() < end:
            m = conn.recv_match(type="ATTITUDE", blocking=True, timeout=0.1)
            last = m or last
        assert last is not None
        sim_s = (last.time_boot_ms - first.time_boot_ms) / 1000
        assert 15 < sim_s < 25, f"20 simulated seconds per wall second: {sim_s}"
        # COM_DISARM_PRFLT (10 s simulated) disarms an idle armed vehicle after ~0.5 s wall.
        assert command(conn, 400, 1) == ACCEPTED
        armed = time.monotonic()
        deadline = armed + 5
        disarmed = None
        while time.monotonic() < deadline and disarmed is None:
            hb = conn.recv_match(type="HEARTBEAT", blocking=True, timeout=0.2)
            if hb is not None and not hb.base_mode & 128:
                disarmed = time.monotonic() - armed
        assert disarmed is not None and disarmed < 2.5, disarmed
        # Commands are still answered at once, and at --speedup max too (below).
        assert command(conn, 176, 1, 3, 0) == ACCEPTED
    finally:
        ap.close()
    fast = Process(rotorpilot_bin, "--speedup", "max")
    try:
        conn = fast.connect()
        assert conn.recv_match(type="HEARTBEAT", blocking=True, timeout=3) is not None
        assert command(conn, 22) == ACCEPTED and command(conn, 400, 1) == ACCEPTED
        assert conn.recv_match(type="EXTENDED_SYS_STATE", condition="EXTENDED_SYS_STATE.landed_state==2",
                               blocking=True, timeout=5) is not None
        assert command(conn, 21) == ACCEPTED, "NAV_LAND answered while the tick runs flat out"
    finally:
        stderr = fast.close()
    assert "stopped after" in stderr


def trajectory_after_arming(log_dir):
    """(x, y, z) per tick from the arming tick, from the flight's ULog file (full profile: one
    record per tick; the file opens at arming)."""
    from pyulog import ULog

    (path,) = sorted(log_dir.glob("log/*/*.ulg"))
    pos = ULog(str(path), ["vehicle_local_position"]).get_dataset("vehicle_local_position").data
    return list(zip(pos["x"].tolist(), pos["y"].tolist(), pos["z"].tolist()))


def scripted_mission(binary, speedup, log_dir):
    """Uploads take-off → waypoint 4 m north → land, arms in AUTO.MISSION and waits for the
    disarm; the ground station acts on the vehicle's simulated clock only."""
    ap = Process(binary, "--speedup", str(speedup), "--log", str(log_dir), "--log-profile", "full")
    try:
        conn = ap.connect()
        assert conn.recv_match(type="HEARTBEAT", blocking=True, timeout=3) is not None
        lat, lon = 473977420, 85455940
        items = [(22, lat, lon, 2.0), (16, lat + 360, lon, 2.0), (21, lat + 360, lon, 0.0)]
        conn.mav.mission_count_send(1, 1, len(items), 0)
        while True:
            m = conn.recv_match(type=["MISSION_REQUEST_INT", "MISSION_ACK"], blocking=True, timeout=3)
            assert m is not None
            if m.get_type() == "MISSION_ACK":
                assert m.type == 0
                break
            cmd, x, y, z = items[m.seq]
            conn.mav.mission_item_int_send(1, 1, m.seq, 6, cmd, 0, 1, 0, 0, 0, NAN, x, y, z, 0)
        assert command(conn, 176, 1, 4, 4) == ACCEPTED
        assert command(conn, 400, 1) == ACCEPTED
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            # A ground station keeps sending its heartbeat; a silent peer expires after 10 s.
            conn.mav.heartbeat_send(6, 8, 0, 0, 0)
            hb = conn.recv_match(type="HEARTBEAT", blocking=True, timeout=0.5)
            if hb is not None and hb.get_srcComponent() == 1 and not hb.base_mode & 128:
                break
        else:
            raise AssertionError("the mission did not end in a disarm")
    finally:
        ap.close()
    return trajectory_after_arming(log_dir)


def test_same_flight_at_1x_and_20x(rotorpilot_bin, tmp_path):
    slow = scripted_mission(rotorpilot_bin, 1, tmp_path / "1x")
    fast = scripted_mission(rotorpilot_bin, 20, tmp_path / "20x")
    flight = min(len(slow), len(fast))
    assert flight > 8000, "take-off, 4 m leg and landing take more than 8 s"
    worst = max(max(abs(a - b) for a, b in zip(p, q)) for p, q in zip(slow[:flight], fast[:flight]))
    assert worst < 1e-3, f"largest difference {worst} m"
    assert abs(slow[flight - 1][0] - 4.0) < 0.1, "flew the leg"


def test_swarm_script_flies_a_formation(rotorpilot_bin):
    ap = Process(rotorpilot_bin, "--count", "3", "--spacing", "4")
    try:
        urls = [arg for v in ap.ready["vehicles"] for arg in ("--connection", f"udpout:{v['api_bind']}")]
        r = subprocess.run([sys.executable, str(SCRIPTS / "swarm.py"), "--count", "3", *urls, "--height", "2",
                            "--radius", "1.5", "--side", "2", "--leg-time", "4"],
                           capture_output=True, text=True, timeout=150, check=False)
    finally:
        ap.close()
    assert r.returncode == 0, r.stdout + r.stderr
    assert "3 vehicles in the air (systems 1, 2, 3)" in r.stdout
    worst = float(next(line for line in r.stdout.splitlines() if line.startswith("max formation error")).split()[3])
    assert worst < 0.15, r.stdout
    assert "3 vehicles landed and disarmed" in r.stdout


def test_swarm_script_usage_errors():
    r = subprocess.run([sys.executable, str(SCRIPTS / "swarm.py"), "--count", "2", "--connection", "udpin:0.0.0.0:0"],
                       capture_output=True, text=True, timeout=30, check=False)
    assert r.returncode == 2 and "--count 2 needs 2 --connection options, not 1" in r.stderr


def test_bench_quick_json(rotorpilot_bin):
    r = subprocess.run([str(rotorpilot_bin), "bench", "--quick", "--json"], capture_output=True, text=True,
                       timeout=120, check=False)
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    assert set(report["headless_ticks_per_s"]) == {"geometric", "hierarchical", "passivity"}
    assert all(rate > 0 for rate in report["headless_ticks_per_s"].values())
    assert report["speedup_max_factor"] > 1, "flat out is faster than real time"
    assert [t["count"] for t in report["trials"]][:1] == [2]
    assert report["largest_realtime_count"] in {0, 2, 4}
    assert 0 < report["first_heartbeat_ms"] < 5000
    ack = report["command_ack"]
    assert ack["samples"] == 50 and 0 < ack["p50_ms"] <= ack["p99_ms"] <= ack["max_ms"]
    assert report["cores"] >= 1
