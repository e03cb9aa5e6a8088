"""pymavlink scripts written for ArduCopter, unchanged, against `rotorpilot run --autopilot
ardupilot` on its default configuration (realistic sensors): the heartbeat pymavlink's mode
tables read, `set_mode('GUIDED')`, `arducopter_arm`, NAV_TAKEOFF in GUIDED, REQUEST_DATA_STREAM,
and a mixed swarm in which each vehicle answers as its own autopilot. Judged from what the
ground station is shown (heartbeats, GLOBAL_POSITION_INT, EKF_STATUS_REPORT)."""
import time

import pytest

from rotorpilot_gcs import mavlink

ARDUPILOT = pytest.mark.rotorpilot(autopilot="ardupilot", speedup=2)
EKF_PRED_POS_HORIZ_ABS = 512


def recv(conn, kinds, timeout=10.0, until=lambda m: True):
    """The first message of `kinds` from the vehicle that satisfies `until`, within `timeout` [s]."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        m = conn.recv_match(type=kinds, blocking=True, timeout=0.2)
        if m is not None and m.get_srcComponent() == 1 and until(m):
            return m
    raise AssertionError(f"no {kinds} within {timeout} s")


def wait_armable(conn, timeout=60.0):
    """DroneKit's `is_armable`: EKF_STATUS_REPORT with the predicted absolute position flag and a
    GPS fix; returns when both are seen."""
    recv(conn, "EKF_STATUS_REPORT", timeout, lambda m: m.flags & EKF_PRED_POS_HORIZ_ABS)
    recv(conn, "GPS_RAW_INT", timeout, lambda m: m.fix_type > 1)


def relative_alt_m(conn):
    return recv(conn, "GLOBAL_POSITION_INT").relative_alt / 1000.0


@ARDUPILOT
def test_a_guided_takeoff_the_arducopter_way(autopilot_factory):
    ap = autopilot_factory(connect=False)
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    assert hb.autopilot == mavlink.MAV_AUTOPILOT_ARDUPILOTMEGA and hb.type == mavlink.MAV_TYPE_QUADROTOR
    assert hb.base_mode & mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0  # pymavlink's default component
    mapping = conn.mode_mapping()
    assert (mapping["GUIDED"], mapping["LAND"], mapping["RTL"], mapping["LOITER"]) == (4, 9, 6, 5)
    # Copter's stream rates start at 0: nothing periodic but the heartbeat until asked.
    heard = set()
    deadline = time.monotonic() + 2.0
    while time.monotonic() < deadline:
        m = conn.recv_match(blocking=True, timeout=0.2)
        if m is not None:
            heard.add(m.get_type())
    assert heard <= {"HEARTBEAT", "STATUSTEXT"}, heard
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 4, 1)
    wait_armable(conn)
    conn.set_mode("GUIDED")
    hb = recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 4)
    assert conn.flightmode == "GUIDED"
    conn.arducopter_arm()
    assert recv(conn, "STATUSTEXT", 10, lambda m: m.text == "Arming motors")
    conn.motors_armed_wait()
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 10)
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_NAV_TAKEOFF)
    assert ack.result == mavlink.MAV_RESULT_ACCEPTED
    assert recv(conn, "GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt >= 9500)
    hb = recv(conn, "HEARTBEAT", 5)
    assert hb.custom_mode == 4 and hb.system_status == mavlink.MAV_STATE_ACTIVE, "still GUIDED, flying"
    time.sleep(2.0)
    assert 9.0 < relative_alt_m(conn) < 11.0, "holds the take-off height"
    conn.set_mode("LAND")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 9)
    assert recv(conn, "STATUSTEXT", 90, lambda m: m.text == "Disarming motors")
    recv(conn, "HEARTBEAT", 10, lambda m: not m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
    assert abs(relative_alt_m(conn)) < 0.5


def north_of_home(conn, metres):
    """(lat, lon) [degE7] `metres` north of home, from HOME_POSITION."""
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_GET_HOME_POSITION, 0, 0, 0, 0, 0, 0, 0, 0)
    home = recv(conn, "HOME_POSITION", 10)
    return home.latitude + round(metres / 111_320.0 * 1e7), home.longitude


def metres_north(conn, lat_e7):
    m = recv(conn, "GLOBAL_POSITION_INT")
    return (m.lat - lat_e7) * 111_320.0 / 1e7, m


@pytest.mark.rotorpilot(autopilot="ardupilot", speedup=4)
def test_guided_goto_speed_heading_and_reposition_as_dronekit_and_mavproxy_send_them(autopilot_factory):
    ap = autopilot_factory(connect=False)
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 10, 1)
    wait_armable(conn)
    conn.set_mode("GUIDED")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 4)
    conn.arducopter_arm()
    conn.motors_armed_wait()
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 10)
    recv(conn, "GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt >= 9500)
    # DroneKit: vehicle.airspeed = 3 (DO_CHANGE_SPEED p1 0), then simple_goto (MISSION_ITEM current 2).
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_DO_CHANGE_SPEED, 0, 0, 3, -1, 0, 0, 0, 0)
    assert recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_DO_CHANGE_SPEED).result == 0
    lat, lon = north_of_home(conn, 30.0)
    conn.mav.mission_item_send(conn.target_system, 0, 0, mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT,
                               mavlink.MAV_CMD_NAV_WAYPOINT, 2, 0, 0, 0, 0, 0, lat / 1e7, lon / 1e7, 15)
    home_lat = lat - round(30.0 / 111_320.0 * 1e7)
    cruise = []  # ground speeds on the middle of the leg [m/s]
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        north, m = metres_north(conn, home_lat)
        if 8.0 < north < 22.0:
            cruise.append(recv(conn, "VFR_HUD").groundspeed)
        if north > 29.0 and abs(m.relative_alt / 1000.0 - 15.0) < 0.5:
            break
    else:
        raise AssertionError(f"never reached the go-to point: {north:.1f} m north, {m.relative_alt} mm up")
    cruise.sort()
    assert cruise and 2.7 < cruise[len(cruise) // 2] < 3.3, f"flew at DO_CHANGE_SPEED's 3 m/s: {cruise}"
    # CONDITION_YAW to 90° absolute: the heading follows and the vehicle stays put.
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_CONDITION_YAW, 0, 90, 20, 1, 0, 0, 0, 0)
    assert recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_CONDITION_YAW).result == 0
    assert recv(conn, "VFR_HUD", 20, lambda m: abs(m.heading - 90) <= 2)
    # MAVProxy's `guided LAT LON ALT` from LOITER: DO_REPOSITION with the mode-change flag.
    conn.set_mode("LOITER")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 5)
    conn.mav.command_int_send(conn.target_system, 0, mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
                              mavlink.MAV_CMD_DO_REPOSITION, 0, 0, -1, 1, 0, 0, home_lat, lon, 12)
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_DO_REPOSITION)
    assert ack.result == mavlink.MAV_RESULT_ACCEPTED
    assert recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 4), "back in GUIDED"
    assert recv(conn, "GLOBAL_POSITION_INT", 60,
                lambda m: abs((m.lat - home_lat) * 111_320.0 / 1e7) < 1.0 and abs(m.relative_alt - 12000) < 500)


@ARDUPILOT
def test_user_takeoff_in_loiter_refusals_and_mode_names(autopilot_factory):
    ap = autopilot_factory(connect=False)
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 4, 1)
    wait_armable(conn)
    conn.set_mode("LOITER")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 5)
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 10)
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_NAV_TAKEOFF)
    assert ack.result == mavlink.MAV_RESULT_FAILED, "not armed"
    # Copter's user take-off in LOITER: it climbs in place and stays in LOITER.
    conn.arducopter_arm()
    conn.motors_armed_wait()
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, 6)
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_NAV_TAKEOFF)
    assert ack.result == mavlink.MAV_RESULT_ACCEPTED
    assert recv(conn, "GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt >= 5700)
    time.sleep(1.0)
    assert 5.5 < relative_alt_m(conn) < 6.5 and recv(conn, "HEARTBEAT", 5).custom_mode == 5
    conn.set_mode("BRAKE")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 17)
    conn.set_mode("LAND")
    recv(conn, "HEARTBEAT", 90, lambda m: not m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
    conn.set_mode("LAND")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 9)
    conn.arducopter_arm()
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_COMPONENT_ARM_DISARM)
    assert ack.result == mavlink.MAV_RESULT_FAILED
    assert recv(conn, "STATUSTEXT", 5).text == "Arm: LAND mode not armable"
    conn.set_mode("POSHOLD")
    assert recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 16)
    assert conn.flightmode == "POSHOLD"
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_DO_SET_MODE, 0, 1, 14, 0, 0, 0, 0, 0)
    ack = recv(conn, "COMMAND_ACK", 10, lambda m: m.command == mavlink.MAV_CMD_DO_SET_MODE)
    assert ack.result == mavlink.MAV_RESULT_FAILED, "FLIP is not emulated"
    text = recv(conn, "STATUSTEXT", 5)
    assert "FLIP" in text.text


@ARDUPILOT
def test_parameters_by_copter_name_as_dronekit_and_pymavlink_fetch_and_set_them(autopilot_factory):
    """DroneKit's connect (PARAM_REQUEST_LIST, every index until the count) and its
    `vehicle.parameters['WPNAV_SPEED'] = 500` (PARAM_SET REAL32, waiting for the echo):
    Copter's banner, Copter's names and units, plain numbers (docs/ardupilot.md §5.1)."""
    ap = autopilot_factory(connect=False)
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0
    conn.param_fetch_all()
    banner = recv(conn, "STATUSTEXT", 10, lambda m: m.text.startswith("ArduCopter V4.5"))
    assert recv(conn, "STATUSTEXT", 5).text == "Frame: QUAD/X", banner.text
    values = {}
    while True:
        m = recv(conn, "PARAM_VALUE", 10)
        values[m.param_index] = (m.param_id, m.param_value, m.param_type)
        if len(values) == m.param_count:
            break
    names = {name: (value, kind) for name, value, kind in values.values()}
    assert names["WPNAV_SPEED"] == (1000.0, mavlink.MAV_PARAM_TYPE_REAL32), "cm/s"
    assert names["RTL_ALT"] == (1500.0, mavlink.MAV_PARAM_TYPE_INT32), "a number, not PX4's bytes"
    assert names["DISARM_DELAY"] == (10.0, mavlink.MAV_PARAM_TYPE_INT8)
    assert "MPC_XY_CRUISE" not in names and "_HASH_CHECK" not in names
    conn.param_set_send("WPNAV_SPEED", 500)
    echo = recv(conn, "PARAM_VALUE", 10, lambda m: m.param_id == "WPNAV_SPEED")
    assert echo.param_value == 500.0
    conn.param_set_send("MPC_XY_CRUISE", 2)
    conn.mav.param_request_read_send(conn.target_system, 0, b"WPNAV_SPEED", -1)
    read = recv(conn, "PARAM_VALUE", 10)
    assert (read.param_id, read.param_value) == ("WPNAV_SPEED", 500.0), "a PX4 name is no name"


def test_a_mixed_swarm_answers_each_as_its_own_autopilot(autopilot_factory):
    ap = autopilot_factory(count=2, autopilot=["px4", "ardupilot"], connect=False)
    assert [v["autopilot"] for v in ap.vehicles] == ["px4", "ardupilot"]
    conn = ap.vehicle.conn
    seen = {}
    deadline = time.monotonic() + 30
    while len(seen) < 2 and time.monotonic() < deadline:
        m = conn.recv_match(type="HEARTBEAT", blocking=True, timeout=0.5)
        if m is not None:
            seen[m.get_srcSystem()] = m.autopilot
    assert seen == {1: mavlink.MAV_AUTOPILOT_PX4, 2: mavlink.MAV_AUTOPILOT_ARDUPILOTMEGA}


def connect(ap):
    """pymavlink's connection to the GCS link (Copter's SR0), aimed at the vehicle."""
    conn = ap.vehicle.conn
    hb = conn.wait_heartbeat(timeout=30)
    conn.target_system, conn.target_component = hb.get_srcSystem(), 0
    return conn


def param(conn, name):
    """PARAM_REQUEST_READ by name (pymavlink's `param_fetch_one`): the PARAM_VALUE answered."""
    conn.param_fetch_one(name)
    return recv(conn, "PARAM_VALUE", 10, lambda m: m.param_id == name)


def param_set(conn, name, value):
    """pymavlink's `param_set_send`: the echo, or for a refusal (the value as it is, then a
    STATUSTEXT) the text."""
    conn.param_set_send(name, value)
    echo = recv(conn, "PARAM_VALUE", 10, lambda m: m.param_id == name)
    try:
        return recv(conn, "STATUSTEXT", 0.5, lambda m: m.text.startswith(f"{name}:")).text
    except AssertionError:
        return echo


def position_rate_hz(conn, seconds=3.0):
    """The rate of GLOBAL_POSITION_INT [Hz of simulated time] over `seconds` of wall time."""
    stamps = []
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        m = conn.recv_match(type="GLOBAL_POSITION_INT", blocking=True, timeout=0.2)
        if m is not None:
            stamps.append(m.time_boot_ms)
    if len(stamps) < 2:
        return 0.0
    return (len(stamps) - 1) / ((stamps[-1] - stamps[0]) / 1000.0)


@ARDUPILOT
def test_sr_rates_sysid_and_failsafe_codes_as_parameters(autopilot_factory):
    """SR0_* are the GCS link's stream group rates (docs/ardupilot.md §5.2): 0 until asked, what
    REQUEST_DATA_STREAM set, and a set of SR0_POSITION changes GLOBAL_POSITION_INT's rate on the
    wire. SYSID_THISMAV is the system id; a Copter code without a behaviour is refused."""
    conn = connect(autopilot_factory(connect=False))
    sr = param(conn, "SR0_POSITION")
    assert (sr.param_value, sr.param_type) == (0.0, mavlink.MAV_PARAM_TYPE_INT16)
    assert position_rate_hz(conn, 1.0) == 0.0, "Copter's SRn_* start at 0"
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, 4, 1)
    assert param(conn, "SR0_POSITION").param_value == 4.0
    assert param(conn, "SR0_PARAMS").param_value == 0.0, "ALL leaves PARAMS alone"
    assert param(conn, "SR1_POSITION").param_value == 0.0, "the API link's"
    assert 3.5 < position_rate_hz(conn) < 4.5
    echo = param_set(conn, "SR0_POSITION", 10)
    assert (echo.param_value, echo.param_type) == (10.0, mavlink.MAV_PARAM_TYPE_INT16)
    assert 9.0 < position_rate_hz(conn) < 11.0
    assert param_set(conn, "SR0_POSITION", 0).param_value == 0.0
    assert position_rate_hz(conn, 1.0) == 0.0
    sysid = param(conn, "SYSID_THISMAV")
    assert (sysid.param_value, sysid.param_type) == (1.0, mavlink.MAV_PARAM_TYPE_INT16)
    assert param_set(conn, "SYSID_THISMAV", 5) == "SYSID_THISMAV: fixed at start (--sysid)"
    assert param_set(conn, "FS_GCS_ENABLE", 3) == "FS_GCS_ENABLE: 3 not emulated (0, 1, 5 or 7)"
    assert param(conn, "FS_GCS_ENABLE").param_value == 0.0, "unchanged"
    assert param(conn, "FENCE_ENABLE").param_value == 0.0, "Copter's fence is off"
    assert param(conn, "FENCE_ALT_MAX").param_value == 100.0
    assert param(conn, "FENCE_RADIUS").param_value == 300.0


def guided_takeoff(conn, height_m, rate_hz=10):
    conn.mav.request_data_stream_send(conn.target_system, 0, mavlink.MAV_DATA_STREAM_ALL, rate_hz, 1)
    wait_armable(conn)
    conn.set_mode("GUIDED")
    recv(conn, "HEARTBEAT", 10, lambda m: m.custom_mode == 4)
    conn.arducopter_arm()
    conn.motors_armed_wait()
    conn.mav.command_long_send(conn.target_system, 0, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, 0, height_m)
    recv(conn, "GLOBAL_POSITION_INT", 60, lambda m: m.relative_alt >= (height_m - 0.5) * 1000)


@ARDUPILOT
def test_fence_enable_0_flies_past_the_fence_and_1_returns(autopilot_factory):
    """FENCE_ENABLE 0 (Copter's default): above FENCE_ALT_MAX (6 m, by its Copter name in the
    `--params` file) without a breach; 1: the breach is said in Copter's words and FENCE_ACTION 1
    returns (the heartbeat shows RTL)."""
    conn = connect(autopilot_factory(connect=False, params={"FENCE_ALT_MAX": 6}))
    assert param(conn, "FENCE_ALT_MAX").param_value == 6.0
    guided_takeoff(conn, 10)
    time.sleep(1.0)
    hb = recv(conn, "HEARTBEAT", 5)
    assert (hb.custom_mode, hb.system_status) == (4, mavlink.MAV_STATE_ACTIVE), "no fence: still GUIDED"
    conn.param_set_send("FENCE_ENABLE", 1)
    # The breach is said at once (Copter acts at once), maybe before the parameter's echo.
    echo = recv(conn, ["PARAM_VALUE", "STATUSTEXT"], 10, lambda m: "fence" in getattr(m, "text", "")
                or getattr(m, "param_id", "") == "FENCE_ENABLE")
    breach = echo if echo.get_type() == "STATUSTEXT" else recv(conn, "STATUSTEXT", 10, lambda m: "fence" in m.text)
    assert (breach.text, breach.severity) == ("Max Alt fence breached", mavlink.MAV_SEVERITY_NOTICE)
    recv(conn, "HEARTBEAT", 20, lambda m: m.custom_mode == 6)


@ARDUPILOT
def test_fs_gcs_enable_1_returns_when_the_ground_station_falls_silent(autopilot_factory):
    """FS_GCS_ENABLE 1 (RTL) is NAV_DLL_ACT 2: the GCS heartbeat heard once in the air, then
    silence past FS_GCS_TIMEOUT, and the vehicle returns (the heartbeat shows RTL)."""
    ap = autopilot_factory(connect=False)
    conn = connect(ap)
    echo = param_set(conn, "FS_GCS_ENABLE", 1)
    assert (echo.param_value, echo.param_type) == (1.0, mavlink.MAV_PARAM_TYPE_INT8)
    assert param_set(conn, "FS_GCS_TIMEOUT", 5).param_value == 5.0
    guided_takeoff(conn, 5)
    ap.vehicle.set_heartbeats(False)  # the package's GCS heartbeat stops: the link falls silent
    ap.vehicle.send_heartbeat()
    lost = recv(conn, "STATUSTEXT", 20, lambda m: "Failsafe" in m.text)
    assert (lost.text, lost.severity) == ("GCS Failsafe", mavlink.MAV_SEVERITY_WARNING)
    recv(conn, "HEARTBEAT", 20, lambda m: m.custom_mode == 6 and m.system_status == mavlink.MAV_STATE_CRITICAL)
