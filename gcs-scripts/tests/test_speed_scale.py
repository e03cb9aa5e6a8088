"""Speed-up and many vehicles: `rotorpilot run --speedup` and `--count`, the swarm script, the
same flight at 1× and 20×, and `rotorpilot bench --quick --json`. Ports are all ephemeral."""
import json
import pathlib
import subprocess
import sys
import time

import pytest
from test_scripts import swarm

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink

# Speed and scale, not what a ground station sees: flown on the exact state (timers in simulated
# time, the same flight at 1x and 20x compared to the millimetre, the swarm's formation to 0.15 m).
pytestmark = pytest.mark.rotorpilot(sensors="ideal")

SCRIPTS = pathlib.Path(__file__).resolve().parents[1]
ACCEPTED = mavlink.MAV_RESULT_ACCEPTED


def result(vehicle, cmd, *params):
    """The MAV_RESULT of one COMMAND_LONG (None without an answer within 2 s)."""
    ack = vehicle.command_ack(cmd, *params, timeout=2)
    return None if ack is None else ack.result


def test_count_gives_separate_vehicles_on_a_grid(autopilot_factory):
    ap = autopilot_factory(count=4, args=["--spacing", "5", "--sysid", "11"])
    vehicles = ap.vehicles
    assert [v["sysid"] for v in vehicles] == [11, 12, 13, 14]
    assert len({v["gcs_bind"] for v in vehicles} | {v["api_bind"] for v in vehicles}) == 8
    api = [int(v["api"].rsplit(":", 1)[1]) for v in vehicles]
    assert api == [api[0] + i for i in range(4)], "vehicle i's API telemetry goes to the first port + i"
    homes = []
    for i, v in enumerate(vehicles):
        vehicle = gcs.Vehicle.connect(f"udpout:{v['gcs_bind']}", 3)
        assert vehicle.conn.target_system == 11 + i
        lat, lon, _ = vehicle.home_position()
        homes.append((lat, lon))
        vehicle.close()
    # A 2 × 2 grid, 5 m apart: rows north, columns east.
    north, east = gcs.geo.global_to_offset(*homes[0], *homes[2])
    assert abs(north - 5) < 0.01 and abs(east) < 0.01 and homes[1][0] == homes[0][0]
    assert homes[1][1] > homes[0][1] and homes[3][1] == homes[1][1]


def test_speedup_runs_every_timer_in_simulated_time(autopilot_factory):
    ap = autopilot_factory(speedup=20)
    conn = ap.vehicle.conn
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
    assert result(ap.vehicle, 400, 1) == ACCEPTED
    armed = time.monotonic()
    deadline = armed + 5
    disarmed = None
    while time.monotonic() < deadline and disarmed is None:
        hb = conn.recv_match(type="HEARTBEAT", blocking=True, timeout=0.2)
        if hb is not None and not hb.base_mode & 128:
            disarmed = time.monotonic() - armed
    assert disarmed is not None and disarmed < 2.5, disarmed
    # Commands are still answered at once, and at --speedup max too (below).
    assert result(ap.vehicle, 176, 1, 3, 0) == ACCEPTED
    ap.stop()
    fast = autopilot_factory(speedup="max")
    assert result(fast.vehicle, 22) == ACCEPTED and result(fast.vehicle, 400, 1) == ACCEPTED
    fast.vehicle.wait_in_air(5)
    assert result(fast.vehicle, 21) == ACCEPTED, "NAV_LAND answered while the tick runs flat out"
    fast.stop()
    assert "stopped after" in fast.stderr_text()


def trajectory_after_arming(log_dir):
    """(x, y, z) per tick from the arming tick, from the flight's ULog file (full profile: one
    record per tick; the file opens at arming)."""
    from pyulog import ULog

    (path,) = sorted(log_dir.glob("log/*/*.ulg"))
    pos = ULog(str(path), ["vehicle_local_position"]).get_dataset("vehicle_local_position").data
    return list(zip(pos["x"].tolist(), pos["y"].tolist(), pos["z"].tolist()))


def scripted_mission(autopilot_factory, speedup, log_dir):
    """Uploads take-off → waypoint 4 m north → land, arms in AUTO.MISSION and waits for the
    disarm; the ground station acts on the vehicle's simulated clock only."""
    ap = autopilot_factory(speedup=speedup, log=log_dir, log_profile="full")
    lat, lon = 473977420, 85455940
    ap.vehicle.upload_mission([gcs.missions.nav_takeoff(lat, lon, 2.0), gcs.missions.nav_waypoint(lat + 360, lon, 2.0),
                               gcs.missions.nav_land(lat + 360, lon)])
    assert result(ap.vehicle, 176, 1, 4, 4) == ACCEPTED
    assert result(ap.vehicle, 400, 1) == ACCEPTED
    ap.vehicle.wait_disarmed(60)  # the mission's end
    ap.stop()
    return trajectory_after_arming(log_dir)


def test_same_flight_at_1x_and_20x(autopilot_factory, tmp_path):
    slow = scripted_mission(autopilot_factory, 1, tmp_path / "1x")
    fast = scripted_mission(autopilot_factory, 20, tmp_path / "20x")
    flight = min(len(slow), len(fast))
    assert flight > 8000, "take-off, 4 m leg and landing take more than 8 s"
    worst = max(max(abs(a - b) for a, b in zip(p, q)) for p, q in zip(slow[:flight], fast[:flight]))
    assert worst < 1e-3, f"largest difference {worst} m"
    assert abs(slow[flight - 1][0] - 4.0) < 0.1, "flew the leg"


def test_swarm_script_flies_a_formation(autopilot_factory):
    ap = autopilot_factory(count=3, args=["--spacing", "4"])
    r, worst = swarm(ap, "--height", "2", "--radius", "1.5", "--side", "2", "--leg-time", "4")
    assert "3 vehicles in the air (systems 1, 2, 3)" in r.stdout
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
