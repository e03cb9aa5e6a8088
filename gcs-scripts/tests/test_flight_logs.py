"""The ULog flight logs rotorpilot writes, read by pyulog (the library behind PX4 Flight Review and
its `ulog_info` / `ulog2csv`): `run --log` (one file per arming, tlog alongside), `sim --out` and
`fly --log`; topics, fields, parameters, logged strings, parameter changes, the tlog agreeing
with the ULog, and what survives a `kill -9`."""
import json
import math
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from pyulog import ULog
from qgc_replay import Qgc, qgc_download, qgc_list

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavutil

# The logs' contents against the flight: flown on the exact state.
pytestmark = pytest.mark.rotorpilot(sensors="ideal")

ROOT = pathlib.Path(__file__).resolve().parents[2]

PX4_TOPICS = {
    "vehicle_attitude": ["q[0]", "q[1]", "q[2]", "q[3]"],
    "vehicle_attitude_setpoint": ["q_d[0]", "thrust_body[2]"],
    "vehicle_angular_velocity": ["xyz[0]", "xyz[1]", "xyz[2]"],
    "vehicle_local_position": ["x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az", "heading"],
    "vehicle_local_position_setpoint": ["x", "y", "z", "vx", "vy", "vz", "yaw"],
    "vehicle_global_position": ["lat", "lon", "alt"],
    "vehicle_status": ["arming_state", "nav_state"],
    "vehicle_land_detected": ["landed", "maybe_landed", "ground_contact"],
    "actuator_motors": ["control[0]", "control[3]"],
    "vehicle_thrust_setpoint": ["xyz[2]"],
    "vehicle_torque_setpoint": ["xyz[0]", "xyz[1]", "xyz[2]"],
    "battery_status": ["voltage_v", "current_a", "remaining"],
    "sensor_combined": ["gyro_rad[0]", "accelerometer_m_s2[2]"],
}
OWN_TOPICS = {
    "external_wrench_estimate": ["force[0]", "force[2]", "torque[2]", "mass"],
    "external_wrench_truth": ["force[0]", "torque[2]", "mass", "mass_mismatch_force"],
    "controller_errors": ["e_p[0]", "e_v[2]", "e_r[0]", "e_omega[2]"],
    "allocation_status": ["thrust", "torque[0]", "saturated"],
}


def topics(ulog):
    return {d.name: d for d in ulog.data_list}


def flight_logs(log_dir):
    return sorted(log_dir.glob("log/*/*.ulg"))


def fly_one_flight(autopilot_factory, log_dir, *args, hover_s=1.0):
    """`run --log log_dir ARGS`: take off, hover `hover_s`, forced disarm; the flight's ULog."""
    ap = autopilot_factory(log=log_dir, args=args)
    ap.vehicle.takeoff()
    time.sleep(hover_s)
    ap.vehicle.disarm(force=True)
    time.sleep(0.3)  # the writer closes the file
    assert ap.stop() == 0
    (path,) = flight_logs(log_dir)
    return path


def test_run_log_writes_one_ulog_per_flight_with_params_messages_and_changes(tmp_path, autopilot_factory):
    log_dir = tmp_path / "log"
    ap = autopilot_factory(log=log_dir)
    # An estimator, so its topic has data.
    ap.vehicle.param_set("RP_EST_ORDER", 1)
    count = gcs.link.latest(ap.vehicle.conn, "PARAM_VALUE").param_count
    ap.vehicle.takeoff()
    ap.vehicle.param_set("MPC_XY_VEL_MAX", 7.5)
    # A hover long enough for the estimate to settle after the climb (whose body drag it saw).
    ap.vehicle.sleep(3.0)
    ap.vehicle.land()
    ap.vehicle.wait_disarmed(30)  # landed and disarmed
    ap.vehicle.takeoff()
    ap.vehicle.disarm(force=True)  # the second flight ends by a forced disarm
    time.sleep(0.3)
    assert ap.stop() == 0
    files = flight_logs(log_dir)
    assert len(files) == 2, files
    day, name = files[0].parent.name, files[0].name
    assert len(day) == 10 and day[4] == "-" and len(name) >= 12 and name[2] == "_", "YYYY-MM-DD/HH_MM_SS.ulg"
    ulog = ULog(str(files[0]))
    data = topics(ulog)
    for name, fields in {**PX4_TOPICS, **OWN_TOPICS}.items():
        assert name in data, name
        for field in fields:
            assert field in data[name].data, (name, field)
        t = data[name].data["timestamp"]
        assert len(t) > 0 and np.all(np.diff(t.astype(np.int64)) >= 0), name
    assert ulog.msg_info_dict["sys_name"] == "rotorpilot" and ulog.msg_info_dict["log_profile"] == "default"
    assert ulog.msg_info_dict["sys_airframe"] == "quad_x" and ulog.msg_info_dict["sys_controller"] == "geometric"
    params = ulog.initial_parameters
    assert len(params) == count and params["RP_EST_ORDER"] == 1 and params["MPC_XY_VEL_MAX"] == pytest.approx(12.0)
    changes = [(name, value) for _, name, value in ulog.changed_parameters]
    assert ("MPC_XY_VEL_MAX", pytest.approx(7.5)) in changes
    texts = [m.message for m in ulog.logged_messages]
    assert "Takeoff detected" in texts and "Landing detected" in texts, texts
    status = data["vehicle_status"].data
    assert status["arming_state"][0] == 2 and status["arming_state"][-1] == 1, "armed to disarmed"
    lpos = data["vehicle_local_position"].data
    assert np.min(lpos["z"]) < -2.4, "the climb is in the log"
    est = data["external_wrench_estimate"].data
    hover = np.interp(est["timestamp"], lpos["timestamp"], lpos["z"]) < -2.4
    assert abs(np.median(est["mass"][hover]) - 1.5) < 0.02, "hovering, quad_x's estimate is its true mass"
    # The second flight starts with its own definitions.
    second = ULog(str(files[1]))
    assert second.initial_parameters["MPC_XY_VEL_MAX"] == pytest.approx(7.5)
    # Default profile: PX4-like rates, not every tick.
    t = data["vehicle_attitude"].data["timestamp"]
    assert np.median(np.diff(t)) == 20_000


def test_ulog_and_tlog_agree_on_the_trajectory(tmp_path, autopilot_factory):
    log_dir = tmp_path / "log"
    path = fly_one_flight(autopilot_factory, log_dir, "--log-profile", "full")
    lpos = ULog(str(path), ["vehicle_local_position"]).get_dataset("vehicle_local_position").data
    assert np.all(np.diff(lpos["timestamp"]) == 1000), "full profile: every 1 ms tick"
    by_us = {int(t): (x, y, z) for t, x, y, z in zip(lpos["timestamp"], lpos["x"], lpos["y"], lpos["z"])}
    tlog = mavutil.mavlink_connection(str(log_dir / "flight.tlog"))
    compared = 0
    while (m := tlog.recv_match(type="LOCAL_POSITION_NED")) is not None:
        if m.get_srcSystem() != 1:
            continue
        # time_boot_ms is the tick's time cut to the millisecond: the tick at that time.
        rec = by_us.get(m.time_boot_ms * 1000)
        if rec is None:
            continue
        assert rec == pytest.approx((m.x, m.y, m.z), abs=1e-5), m.time_boot_ms
        compared += 1
    assert compared > 20, "the tlog's positions during the flight are in the ULog"


def test_kill_9_keeps_every_record_older_than_200_ms(tmp_path, autopilot_factory):
    """After SIGKILL, the flight's ULog holds every tick and flight.tlog every frame older than 200 ms."""
    log_dir = tmp_path / "log"
    ap = autopilot_factory(log=log_dir, log_profile="full")
    ap.vehicle.takeoff()
    att = ap.vehicle.wait("ATTITUDE", timeout=2)
    received = time.monotonic()
    ap.proc.send_signal(signal.SIGKILL)
    killed_wall = time.time()
    sim_at_kill = att.time_boot_ms / 1000 + (time.monotonic() - received)
    assert ap.stop() == -signal.SIGKILL
    (path,) = flight_logs(log_dir)
    att = ULog(str(path), ["vehicle_attitude"]).get_dataset("vehicle_attitude").data
    t = att["timestamp"]
    assert np.all(np.diff(t) == 1000), "no tick lost"
    assert t[-1] / 1e6 >= sim_at_kill - 0.2, (t[-1], sim_at_kill)
    log = mavutil.mavlink_connection(str(log_dir / "flight.tlog"))
    last = None
    while (m := log.recv_match()) is not None:
        last = m
    assert last is not None and last._timestamp >= killed_wall - 0.2, (last._timestamp, killed_wall)


def test_sim_writes_every_tick_of_the_homework_run(tmp_path, rotorpilot):
    out = tmp_path / "ex4"
    summary = json.loads(rotorpilot("sim", str(ROOT / "scenarios" / "ex4_estimator.toml"), "--out", str(out)).stdout)
    path = out / "run.ulg"
    assert not (out / "run.csv").exists(), "CSV only on request"
    size_per_s = path.stat().st_size / summary["sim_time_s"]
    # Every tick of the state, the control and the estimate, and of the true state beside it.
    assert size_per_s <= 420e3, f"{size_per_s / 1e3:.0f} KB per simulated second"
    ulog = ULog(str(path))
    data = topics(ulog)
    for name in ["vehicle_attitude", "vehicle_local_position", "controller_errors", "allocation_status",
                 "external_wrench_estimate"]:
        assert len(data[name].data["timestamp"]) == round(summary["sim_time_s"] / summary["dt_s"]), name
    est = data["external_wrench_estimate"].data
    truth = data["external_wrench_truth"].data
    assert est["force[0]"][-1] == pytest.approx(truth["force[0]"][-1], abs=5e-3)
    assert est["force[2]"][-1] == pytest.approx(truth["force[2]"][-1] + truth["mass_mismatch_force"][-1], abs=5e-3)
    assert est["torque[2]"][-1] == pytest.approx(truth["torque[2]"][-1], abs=5e-3)
    assert truth["mass"][-1] == pytest.approx(1.7) and ulog.msg_info_dict["log_profile"] == "full"
    assert est["mass"][-1] == pytest.approx(summary["estimate"]["mass_kg"], abs=1e-5)
    csv_dir = tmp_path / "csv"
    ulog2csv = pathlib.Path(sys.executable).parent / "ulog2csv"
    subprocess.run([str(ulog2csv), "-o", str(csv_dir), str(path)], check=True, capture_output=True)
    assert (csv_dir / "run_external_wrench_estimate_0.csv").stat().st_size > 0, "ulog2csv exports it"


def test_fly_log_and_bad_paths(tmp_path, rotorpilot_bin):
    path = tmp_path / "fly.ulg"
    r = subprocess.run([str(rotorpilot_bin), "fly", "--duration", "6", "--log", str(path)], capture_output=True,
                       text=True, timeout=60, check=False)
    assert r.returncode == 0, r.stderr
    pos = ULog(str(path), ["vehicle_local_position"]).get_dataset("vehicle_local_position").data
    assert len(pos["timestamp"]) == 6000 and math.isclose(pos["z"][-1] - pos["z"][0], -2.0, abs_tol=0.02)
    r = subprocess.run([str(rotorpilot_bin), "fly", "--duration", "1", "--log", str(tmp_path / "no" / "such" / "x")],
                       capture_output=True, text=True, timeout=60, check=False)
    assert r.returncode == 0, "the directory is created"
    blocker = tmp_path / "file"
    blocker.write_text("")
    r = subprocess.run([str(rotorpilot_bin), "fly", "--duration", "1", "--log", str(blocker / "x.ulg")],
                       capture_output=True, text=True, timeout=60, check=False)
    assert r.returncode != 0 and str(blocker / "x.ulg") in r.stderr


def test_a_flight_log_downloads_as_qgc_does_equal_to_the_file(tmp_path, autopilot_factory):
    """The log of a real flight: listed while it is being written, then downloaded after the
    disarm as QGroundControl downloads it (a piece lost and asked again), equal to the file on
    disk, and read by pyulog."""
    log_dir = tmp_path / "log"
    ap = autopilot_factory(log=log_dir)
    ap.vehicle.takeoff()
    station = Qgc(ap)
    during = qgc_list(station)
    assert len(during) == 1 and during[0].size > 0, "the log being written is listed"
    ap.vehicle.disarm(force=True)
    time.sleep(0.5)  # the writer closes the file
    entries = qgc_list(station)
    (path,) = flight_logs(log_dir)
    size = path.stat().st_size
    assert entries[0].size == size > during[0].size
    data = qgc_download(station, 0, size, drop={90 * 7})
    station.close()
    assert ap.stop() == 0
    assert data == path.read_bytes()
    copy = tmp_path / "downloaded.ulg"
    copy.write_bytes(data)
    assert "vehicle_attitude" in topics(ULog(str(copy)))


def test_estimate_replays_a_run_log_at_its_default_rate(tmp_path, autopilot_factory, rotorpilot_bin):
    """`run --log`'s default profile logs the estimator's inputs together every 20 ms: the
    offline estimator at --ts 0.02 recovers the 0.2 kg the controller does not believe in."""
    frame = tmp_path / "heavy.toml"
    frame.write_text((ROOT / "airframes" / "quad_x.toml").read_text() + "\n[fc]\nmass = 1.3 # [kg] believed\n")
    path = fly_one_flight(autopilot_factory, tmp_path / "log", "--airframe", str(frame), hover_s=8.0)
    args = ["estimate", "--log", str(path), "--mass", "1.3", "--inertia", "0.029125,0.029125,0.055225",
            "--order", "1", "--ripple-db", "3", "--wp", "2"]
    r = subprocess.run([str(rotorpilot_bin), *args, "--ts", "0.02"], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert result["mass_estimate"] == pytest.approx(1.5, rel=0.005) and result["samples"] > 400
    r = subprocess.run([str(rotorpilot_bin), *args], capture_output=True, text=True, check=False)
    assert r.returncode != 0 and "--ts 0.02" in r.stderr, "at the default --ts it says which step to use"
