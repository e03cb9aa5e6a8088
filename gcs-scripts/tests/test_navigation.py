"""Flying on the navigation filter's estimate with the sensor suite (`rotorpilot run --sensors realistic`),
and PX4's reactions to sensor failures injected as MAVSDK and QGroundControl inject them
(MAV_CMD_INJECT_FAILURE behind SYS_FAILURE_EN): a GPS lost during a mission ends in a level
descent without position and a gentle touch-down (judged on the logged truth); a lost barometer
or compass lets the mission fly on. MAVSDK's own failure_injection.py is flown unchanged in
test_mavsdk_examples.py."""
import math

import pytest
from pyulog import ULog

from rotorpilot_gcs import mavlink
from rotorpilot_gcs.geo import offset_to_global
from rotorpilot_gcs.missions import nav_return_to_launch, nav_takeoff, nav_waypoint

pytestmark = pytest.mark.rotorpilot(sensors="realistic", speedup=4, log=True,
                                    params={"SYS_FAILURE_EN": 1, "MPC_XY_CRUISE": 4})

INJECT_FAILURE = 420
# FAILURE_UNIT and FAILURE_TYPE (MAVSDK's FailureUnit / FailureType).
GPS, BARO, MAG = 4, 3, 2
OFF = 1


def mission(autopilot, legs_m=(20, 20), alt=10.0):
    """Take-off to `alt`, a square of `legs_m` north then east and back, then RTL."""
    vehicle = autopilot.vehicle
    lat, lon, _ = vehicle.home_position()
    north, east = legs_m
    corners = [(north, 0), (north, east), (0, east), (0, 0)]
    points = [offset_to_global(lat, lon, n, e) for n, e in corners]
    vehicle.upload_mission([nav_takeoff(*offset_to_global(lat, lon, 0, 0), alt)]
                           + [nav_waypoint(*p, alt) for p in points] + [nav_return_to_launch()])
    vehicle.set_mode("AUTO.MISSION")
    vehicle.arm()


def inject(autopilot, unit, kind=OFF):
    ack = autopilot.vehicle.command(INJECT_FAILURE, unit, kind, 0)
    assert ack.result == mavlink.MAV_RESULT_ACCEPTED


def texts_until(autopilot, done, timeout):
    """STATUSTEXTs until `done(message)` holds for one of them or `timeout` [s] passes."""
    seen = []
    for _ in range(int(timeout * 20)):
        m = autopilot.vehicle.recv(0.05)
        if m is not None and m.get_type() == "STATUSTEXT":
            seen.append(m.text)
            if done(m.text):
                break
    return seen


def flight_truth(autopilot):
    """The true path of the (only) flight: (t [s], north, east, down [m], down speed [m/s])."""
    [path] = autopilot.flight_logs()
    d = {x.name: x.data for x in ULog(str(path), ["vehicle_local_position_groundtruth"]).data_list}
    g = d["vehicle_local_position_groundtruth"]
    return list(zip(g["timestamp"] / 1e6, g["x"], g["y"], g["z"], g["vz"]))


def test_gps_lost_in_a_mission_descends_level_and_lands_gently(autopilot):
    mission(autopilot)
    autopilot.vehicle.wait("MISSION_ITEM_REACHED", lambda m: m.seq == 1, timeout=60)  # the first corner
    inject(autopilot, GPS)
    # Dead reckoning along the mission for EKF2_NOAID_TOUT (5 s), then the descent.
    texts = texts_until(autopilot, lambda t: t == "No position estimate: descending", 30)
    assert "GPS lost: dead reckoning" in texts and texts[-1] == "No position estimate: descending", texts
    autopilot.vehicle.wait_mode("AUTO.LAND", 5)
    descent_s = autopilot.vehicle.local_position().time_boot_ms / 1e3
    autopilot.vehicle.wait_disarmed(timeout=90)
    truth = flight_truth(autopilot)
    ground = max(p[3] for p in truth)
    touchdown = max(p[4] for p in truth if ground - p[3] < 0.3 and p[0] > truth[0][0] + 5)
    assert touchdown < 1.0, f"touched down at {touchdown:.2f} m/s"
    start = min(truth, key=lambda p: abs(p[0] - descent_s))
    final = truth[-1]
    drift = math.hypot(final[1] - start[1], final[2] - start[2])
    # Cruising at 4 m/s when the descent began, it stops on its dead-reckoned velocity (which
    # drifts: the filter holds its position only by a pseudo-measurement by then).
    assert drift < 20.0, f"landed {drift:.1f} m from where the descent began"


@pytest.mark.parametrize("unit,announced", [(BARO, "Barometer lost"),
                                            (MAG, "Compass lost: heading from gyro and GPS")])
def test_baro_or_compass_lost_in_a_mission_flies_on(autopilot, unit, announced):
    mission(autopilot)
    autopilot.vehicle.wait("MISSION_ITEM_REACHED", lambda m: m.seq == 1, timeout=60)
    inject(autopilot, unit)
    texts = texts_until(autopilot, lambda t: t == announced, 10)
    assert announced in texts, texts
    # The mission carries on to its last corner, returns and lands.
    autopilot.vehicle.wait("MISSION_ITEM_REACHED", lambda m: m.seq == 4, timeout=90)
    autopilot.vehicle.wait_mode("AUTO.RTL", 10)
    autopilot.vehicle.wait_disarmed(timeout=90)
    final = flight_truth(autopilot)[-1]
    assert math.hypot(final[1], final[2]) < 3.0, "landed at home"


def test_sensor_failure_injection_needs_sys_failure_en(autopilot_factory):
    ap = autopilot_factory(params={"SYS_FAILURE_EN": 0})
    ack = ap.vehicle.command_ack(INJECT_FAILURE, GPS, OFF, 0)
    assert ack.result == mavlink.MAV_RESULT_DENIED


def test_ekf_status_report_on_request_as_ardupilot_ground_stations_read_it(vehicle):
    """EKF_STATUS_REPORT (ArduPilot's dialect) is off by default, as in PX4; asked for, it carries
    the filter's flags and the square roots of its test ratios, decoded by pymavlink's default
    ardupilotmega dialect as MAVProxy and QGroundControl decode it."""
    ekf = 193
    assert vehicle.command(mavlink.MAV_CMD_GET_MESSAGE_INTERVAL, ekf).result == mavlink.MAV_RESULT_ACCEPTED
    interval = vehicle.wait("MESSAGE_INTERVAL", lambda m: m.message_id == ekf, timeout=5)
    assert interval.interval_us == -1, "off until asked for"
    report = vehicle.request_message(ekf, "EKF_STATUS_REPORT")
    good = (mavlink.EKF_ATTITUDE | mavlink.EKF_VELOCITY_HORIZ | mavlink.EKF_VELOCITY_VERT
            | mavlink.EKF_POS_HORIZ_ABS | mavlink.EKF_POS_VERT_ABS)
    assert report.flags & good == good, hex(report.flags)
    assert not report.flags & mavlink.EKF_UNINITIALIZED
    for name in ("velocity_variance", "pos_horiz_variance", "pos_vert_variance", "compass_variance"):
        assert 0.0 <= getattr(report, name) < 0.8, (name, report)
    assert vehicle.command(mavlink.MAV_CMD_SET_MESSAGE_INTERVAL, ekf, 200_000).result == mavlink.MAV_RESULT_ACCEPTED
    reports = [m for m in (vehicle.recv(0.05) for _ in range(60))
               if m is not None and m.get_type() == "EKF_STATUS_REPORT"]
    assert len(reports) >= 5, "streamed at the interval set"
