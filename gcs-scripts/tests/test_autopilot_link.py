"""`rotorpilot run` driven over MAVLink by pymavlink: heartbeat, command/ACK rules, modes,
take-off → hold → land → auto-disarm. The autopilot is the plugin's `autopilot` fixture (ports
all ephemeral); `command_ack` sends one COMMAND_LONG and returns its ACK whatever the result."""
import math
import pathlib
import time

import pytest

import rotorpilot_gcs as gcs
from rotorpilot_gcs import custom_mode, mavlink
from rotorpilot_gcs.params import float_bits_to_int, int32_bits

# The link's behaviours run on `rotorpilot run`'s default configuration (realistic sensors and the
# navigation filter), as a ground station meets the vehicle. A test that measures something else
# than the link (a flight's centimetres, an estimator, the IMU's values) flies on the exact state,
# marked EXACT_STATE with the reason (the navigation filter and sensor failures have their own
# tests, test_navigation.py).
EXACT_STATE = pytest.mark.rotorpilot(sensors="ideal")

ACCEPTED, TEMPORARILY_REJECTED = mavlink.MAV_RESULT_ACCEPTED, mavlink.MAV_RESULT_TEMPORARILY_REJECTED
DENIED, UNSUPPORTED, FAILED = mavlink.MAV_RESULT_DENIED, mavlink.MAV_RESULT_UNSUPPORTED, mavlink.MAV_RESULT_FAILED
NAN = float("nan")
ROOT = pathlib.Path(__file__).resolve().parents[2]
HOME = gcs.geo.DEFAULT_HOME
HOME_LAT, HOME_LON = gcs.geo.offset_to_global(HOME[0], HOME[1], 0.0, 0.0)  # [degE7]
METRE_LAT, METRE_LON = gcs.geo.deg_e7_per_metre(HOME[0])  # degE7 per metre north, east


def at(north_m, east_m):
    """(lat, lon) [degE7] of the point `north_m` / `east_m` metres from home."""
    return gcs.geo.offset_to_global(HOME[0], HOME[1], north_m, east_m)


def test_ready_line_and_first_heartbeat(autopilot):
    assert autopilot.ready["event"] == "ready" and autopilot.sysid == 1
    assert autopilot.gcs_bind.startswith("127.0.0.1:") and not autopilot.gcs_bind.endswith(":0")
    hb = autopilot.vehicle.wait_heartbeat()
    assert hb.get_srcSystem() == 1 and hb.get_srcComponent() == 1
    assert hb.autopilot == mavlink.MAV_AUTOPILOT_PX4 and hb.type == mavlink.MAV_TYPE_QUADROTOR
    assert hb.base_mode & 1 and not hb.base_mode & 128
    assert hb.custom_mode == custom_mode("AUTO.LOITER")


def test_command_rules(vehicle):
    assert vehicle.command_ack(31999).result == UNSUPPORTED, "ids the crate does not know"
    assert vehicle.command_ack(mavlink.MAV_CMD_DO_SET_SERVO, 1, 1500).result == UNSUPPORTED
    ack = vehicle.command_ack(400, 2.0)
    assert ack.result == DENIED and (ack.target_system, ack.target_component) == (255, 190)
    assert "param1" in vehicle.wait("STATUSTEXT", timeout=2).text
    assert vehicle.command_ack(400, 1.0, target=(7, 1)) is None, "other systems' commands are ignored"
    assert vehicle.command_ack(176, 1, 1, 0).result == TEMPORARILY_REJECTED, "MANUAL needs sticks"
    assert vehicle.command_ack(176, 1, 4, 12).result == DENIED
    assert vehicle.command_ack(176, 1, 4, 4).result == TEMPORARILY_REJECTED, "no mission"
    assert vehicle.command_ack(176, 1, 3, 0, target=(0, 0)).result == ACCEPTED
    vehicle.wait_mode("POSCTL", 2)  # shows in the next heartbeat
    # SET_MODE (#11), QGC's way: no ACK, the heartbeat confirms.
    vehicle.conn.mav.set_mode_send(1, 1, custom_mode("AUTO.LOITER"))
    vehicle.wait_mode("AUTO.LOITER", 2)
    # DO_SET_STANDARD_MODE (262): POSITION_HOLD → POSCTL; ORBIT needs the air; CRUISE is not
    # available → FAILED.
    assert vehicle.command_ack(262, 1).result == ACCEPTED
    vehicle.wait_mode("POSCTL", 2)
    assert vehicle.command_ack(262, 2).result == TEMPORARILY_REJECTED
    assert vehicle.wait("STATUSTEXT", timeout=2).text == "Mode ORBIT: not in the air"
    assert vehicle.command_ack(262, 3).result == FAILED
    assert "Standard mode 3" in vehicle.wait("STATUSTEXT", timeout=2).text


@EXACT_STATE  # the take-off's precision: 5 cm from the point above home (a realistic GPS wanders by dm)
def test_takeoff_hold_land_and_auto_disarm(vehicle):
    assert vehicle.command_ack(22).result == ACCEPTED, "NAV_TAKEOFF while disarmed (PX4)"
    vehicle.wait_armable()
    assert vehicle.command_ack(400, 1.0).result == ACCEPTED
    armed = vehicle.wait_armed(2)
    assert armed.system_status == mavlink.MAV_STATE_ACTIVE
    vehicle.wait_in_air(10)
    pos = vehicle.wait("LOCAL_POSITION_NED", timeout=3)
    assert abs(pos.z + 2.5) < 0.05 and math.hypot(pos.x, pos.y) < 0.05, "MIS_TAKEOFF_ALT above home"
    glob = vehicle.wait("GLOBAL_POSITION_INT", timeout=3)
    assert abs(glob.relative_alt - 2500) < 50 and abs(glob.alt - 490_500) < 50
    assert vehicle.command_ack(400, 0.0).result == TEMPORARILY_REJECTED, "no disarm in the air"
    assert vehicle.command_ack(21).result == ACCEPTED
    vehicle.wait("STATUSTEXT", lambda m: "Disarmed" in m.text, 15)
    hb = vehicle.wait_disarmed(3)
    assert hb.system_status == mavlink.MAV_STATE_STANDBY
    vehicle.wait_on_ground(3)


def test_sigterm_stops_cleanly(autopilot):
    autopilot.proc.terminate()
    assert autopilot.proc.wait(timeout=10) == 0
    assert "stopped after" in autopilot.stderr_text()


def test_discovery_services(vehicle):
    assert vehicle.command_ack(512, 148).result == ACCEPTED
    assert vehicle.wait("AUTOPILOT_VERSION", timeout=2).capabilities & 8192, "MAVLINK2"
    assert vehicle.command_ack(520).result == ACCEPTED
    vehicle.wait("AUTOPILOT_VERSION", timeout=2)
    assert vehicle.command_ack(410).result == ACCEPTED
    home = vehicle.wait("HOME_POSITION", timeout=2)
    assert (home.latitude, home.longitude, home.altitude) == (473977420, 85455940, 488000)
    assert vehicle.command_ack(512, 435, 1).result == ACCEPTED, "AVAILABLE_MODES"
    assert vehicle.command_ack(512, 999).result == DENIED, "a message that is not produced"
    vehicle.conn.mav.ping_send(123456, 9, 0, 0)
    ping = vehicle.wait("PING", lambda m: m.seq == 9, 2)
    assert ping.time_usec == 123456 and ping.target_system == 255
    vehicle.conn.mav.timesync_send(0, 777)
    assert vehicle.wait("TIMESYNC", lambda m: m.ts1 == 777, 2).tc1 > 0
    payload = [0] * 251
    payload[0:2] = [5, 0]
    payload[3] = 4  # OpenFileRO
    vehicle.conn.mav.file_transfer_protocol_send(0, 1, 1, payload)
    ftp = vehicle.wait("FILE_TRANSFER_PROTOCOL", timeout=2)
    assert list(ftp.payload[:6]) == [6, 0, 0, 129, 1, 4] and ftp.payload[12] == 10


def test_duplicates_and_command_int(vehicle):
    first = vehicle.command_ack(176, 1, 3, 0)
    again = vehicle.command_ack(176, 1, 3, 0)
    assert first.result == again.result == ACCEPTED, "a retransmission gets the cached result"
    # COMMAND_INT NAV_TAKEOFF with z AMSL 493 m = 5 m above home.
    vehicle.conn.mav.command_int_send(1, 1, 0, 22, 0, 0, NAN, 0, 0, NAN, 2147483647, 2147483647, 493.0)
    assert vehicle.wait("COMMAND_ACK", lambda m: m.command == 22, 2).result == ACCEPTED
    vehicle.wait_armable()
    assert vehicle.command_ack(400, 1.0).result == ACCEPTED
    vehicle.wait("LOCAL_POSITION_NED", lambda m: abs(m.z + 5.0) < 0.05, 12, what="5 m above home")


def test_parameter_protocol(autopilot):
    autopilot.vehicle.conn.mav.param_request_list_send(1, 1)
    values = {}
    hashes = []
    deadline = time.monotonic() + 5
    count = None
    while time.monotonic() < deadline and (count is None or len(values) < count):
        m = autopilot.vehicle.conn.recv_match(type="PARAM_VALUE", blocking=True, timeout=1)
        if m is not None and m.param_id == "_HASH_CHECK":
            # PX4 sends the hash of the whole list first, outside the enumeration.
            assert m.param_index == 65535 and not values, m
            hashes.append(m)
        elif m is not None:
            count = m.param_count
            values[m.param_id] = m
    assert len(hashes) == 1
    assert count is not None and len(values) == count >= 50
    assert values["MIS_TAKEOFF_ALT"].param_value == 2.5
    assert values["RP_CTRL"].param_type == 6 and float_bits_to_int(values["RP_CTRL"].param_value) == 0
    index = values["RP_GEO_KP_Z"].param_index
    autopilot.vehicle.conn.mav.param_request_read_send(1, 1, b"", index)
    by_index = autopilot.vehicle.wait("PARAM_VALUE", lambda m: m.param_index == index, 2)
    assert by_index.param_id == "RP_GEO_KP_Z"
    # fsr gains scaled to quad_x keep K_p (mass 1.5 kg on both).
    assert by_index.param_value == 25.0

    assert autopilot.vehicle.param_set("MIS_TAKEOFF_ALT", 4.0) == 4.0
    with pytest.raises(gcs.ParamError) as refused:
        autopilot.vehicle.param_set("RP_CTRL", 5)  # INT32, as the autopilot declares it
    assert "the autopilot kept 0" in str(refused.value), "refused: the unchanged value is echoed"
    assert "RP_CTRL" in str(refused.value).split("kept 0", 1)[1], "with the STATUSTEXT naming it"
    # PARAM_ERROR (345) is newer than pymavlink's dialect; the STATUSTEXT says it too.
    with pytest.raises(gcs.ParamError, match="NO_SUCH_PARAM"):
        autopilot.vehicle.param_set("NO_SUCH_PARAM", 1.0, int32=False)

    # The new take-off altitude is used.
    assert autopilot.vehicle.command_ack(22).result == ACCEPTED
    autopilot.vehicle.wait_armable()
    assert autopilot.vehicle.command_ack(400, 1.0).result == ACCEPTED
    autopilot.vehicle.wait("LOCAL_POSITION_NED", lambda m: abs(m.z + 4.0) < 0.05, 12, what="4 m above home")


@EXACT_STATE  # bumpless to 5 cm: the controllers' precision, below the realistic GPS's wander
def test_controller_and_estimator_switch_in_flight(vehicle):
    vehicle.takeoff()
    for name, value in [("RP_CTRL", 2), ("RP_EST_ORDER", 1), ("RP_COMP", 1), ("RP_CTRL", 1)]:
        assert vehicle.param_set(name, value) == value
        # Bumpless: the hover stays within 5 cm while the law or the estimator changes.
        end = time.monotonic() + 1.5
        while time.monotonic() < end:
            m = vehicle.conn.recv_match(type="ATTITUDE", blocking=True, timeout=1)
            pos = vehicle.conn.messages.get("LOCAL_POSITION_NED")
            if pos is not None:
                assert abs(pos.z + 2.5) < 0.05 and math.hypot(pos.x, pos.y) < 0.05, (name, pos)
            assert m is None or abs(m.roll) < 0.05


def hold_setpoint(autopilot, x, y, z, seconds):
    """Streams the LOCAL_NED position setpoint (20 Hz) for `seconds`; the last LOCAL_POSITION_NED."""
    autopilot.vehicle.set_setpoint(x, y, z)
    autopilot.vehicle.sleep(seconds)
    return gcs.link.latest(autopilot.vehicle.conn, "LOCAL_POSITION_NED")


def test_offboard_square_and_setpoint_loss(autopilot):
    autopilot.vehicle.takeoff()
    assert autopilot.vehicle.command_ack(176, 1, 6, 0).result == TEMPORARILY_REJECTED, "no setpoint stream yet"
    hold_setpoint(autopilot, 0, 0, -2.5, 0.3)
    assert autopilot.vehicle.command_ack(176, 1, 6, 0).result == ACCEPTED
    autopilot.vehicle.wait_mode("OFFBOARD", 2)
    for x, y in [(2, 0), (2, 2), (0, 2), (0, 0)]:
        pos = hold_setpoint(autopilot, x, y, -2.5, 4.0)
        assert math.hypot(pos.x - x, pos.y - y) < 0.1 and abs(pos.z + 2.5) < 0.1, (x, y, pos)
    autopilot.vehicle.stop_setpoints()
    # A refused setpoint (force bit) says why.
    autopilot.vehicle.conn.mav.set_position_target_local_ned_send(0, 1, 1, 1, 2552 | 512, 0, 0, -2.5,
                                                                  0, 0, 0, 0, 0, 0, 0, 0)
    autopilot.vehicle.wait("STATUSTEXT", lambda m: "force" in m.text, 2)
    # No more setpoints: after COM_OF_LOSS_T the vehicle holds position in POSCTL.
    autopilot.vehicle.wait("STATUSTEXT", lambda m: "Offboard lost" in m.text, 3)
    autopilot.vehicle.wait_mode("POSCTL", 2)
    time.sleep(1.0)
    pos = autopilot.vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert math.hypot(pos.x, pos.y) < 0.1 and abs(pos.z + 2.5) < 0.1


def test_offboard_body_frame_velocity(vehicle):
    vehicle.command_ack(22)
    vehicle.wait_armable()
    vehicle.command_ack(400, 1.0)
    vehicle.wait_in_air(10)
    start = vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    vehicle.conn.mav.set_position_target_local_ned_send(0, 1, 1, 8, 1479, 0, 0, 0, 1.0, 0, 0, 0, 0, 0, 0, 0)
    assert vehicle.command_ack(176, 1, 6, 0).result == ACCEPTED
    end = time.monotonic() + 8.0
    pos = start
    while time.monotonic() < end and pos.x - start.x < 2.0:
        # MAVSDK's body-frame velocity: 1 m/s forward (heading 0 → north), no yaw rate.
        vehicle.conn.mav.set_position_target_local_ned_send(0, 1, 1, 8, 1479, 0, 0, 0, 1.0, 0, 0, 0, 0, 0, 0, 0)
        vehicle.conn.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.05)
        pos = vehicle.conn.messages["LOCAL_POSITION_NED"]
    assert pos.x - start.x >= 2.0, "flew forward"
    assert abs(pos.vx - 1.0) < 0.1 and abs(pos.vy) < 0.1 and abs(pos.y - start.y) < 0.1


def follow_mission(autopilot, waypoints, first_seq, count, timeout):
    """Collects MISSION_ITEM_REACHED until `count` items are reached; the first GLOBAL_POSITION_INT
    after reaching waypoint item `first_seq + i` must be within 3 m of `waypoints[i]` (north, east)
    at 3 m: a waypoint flown through counts as reached within NAV_ACC_RAD (2 m), as PX4's, and
    GLOBAL_POSITION_INT streams at 5 Hz. Returns (reached, checked)."""
    reached, checked = [], []
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and len(reached) < count:
        m = autopilot.vehicle.recv(1.0)
        if m is None:
            continue
        if m.get_type() == "MISSION_ITEM_REACHED":
            reached.append(m.seq)
        elif (m.get_type() == "GLOBAL_POSITION_INT" and reached and 0 <= reached[-1] - first_seq < len(waypoints)
              and reached[-1] not in checked):
            lat, lon = at(*waypoints[reached[-1] - first_seq])
            assert abs(m.lat - lat) < 3.0 * METRE_LAT and abs(m.lon - lon) < 3.0 * METRE_LON, m
            assert abs(m.relative_alt - 3000) < 300
            checked.append(reached[-1])
    return reached, checked


def square_mission(points, alt=3.0):
    """NAV_WAYPOINT at each (north, east) [m] at `alt` [m above home], then RETURN_TO_LAUNCH."""
    return [gcs.missions.nav_waypoint(*at(x, y), alt) for x, y in points] + [gcs.missions.nav_return_to_launch()]


@EXACT_STATE  # the mission against the plan (landed within 0.2 m of home): the GPS's wander is as large
def test_mission_upload_download_fly_and_return(autopilot):
    assert autopilot.vehicle.command_ack(176, 1, 4, 4).result == TEMPORARILY_REJECTED, "no mission yet"
    square = [gcs.missions.nav_takeoff(HOME_LAT, HOME_LON, 3.0)] + square_mission([(5, 0), (5, 5), (0, 5), (0, 0)])
    autopilot.vehicle.upload_mission(square)
    got = autopilot.vehicle.download_mission()
    assert [m.command for m in got] == [22, 16, 16, 16, 16, 20] and got[2].x == at(5, 5)[0]
    assert got == square, "the autopilot stores what went up"
    # A bad mission is refused with the item's result and leaves the stored one unchanged.
    with pytest.raises(gcs.MissionError) as refused:
        autopilot.vehicle.upload_mission(square[:2] + [gcs.missions.MissionItem(31000)])
    assert refused.value.result == mavlink.MAV_MISSION_UNSUPPORTED
    assert len(autopilot.vehicle.download_mission()) == 6
    current = autopilot.vehicle.wait("MISSION_CURRENT", timeout=3)
    assert current.total == 6 and current.mission_state == 2, "NOT_STARTED"

    autopilot.vehicle.param_set("RTL_RETURN_ALT", 5.0)
    assert autopilot.vehicle.command_ack(176, 1, 4, 4).result == ACCEPTED
    autopilot.vehicle.wait_armable()
    assert autopilot.vehicle.command_ack(400, 1.0).result == ACCEPTED
    reached, checked = follow_mission(autopilot, [(5, 0), (5, 5), (0, 5), (0, 0)], 1, 6, 60)
    assert reached == [0, 1, 2, 3, 4, 5]
    assert len(checked) >= 3
    autopilot.vehicle.wait_mode("AUTO.RTL", 3)  # the RTL item switches to AUTO.RTL
    autopilot.vehicle.wait("STATUSTEXT", lambda m: "Disarmed" in m.text, 40)
    pos = autopilot.vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert math.hypot(pos.x, pos.y) < 0.2 and abs(pos.z) < 0.2, "landed at home"


@EXACT_STATE  # the wrench estimator's precision: mass within 0.5 %, force within 0.02 N
def test_live_wrench_estimate(tmp_path, autopilot_factory):
    """The estimator's external force and mass estimate stream on DEBUG_VECT / NAMED_VALUE_FLOAT."""
    frame = tmp_path / "heavy.toml"
    frame.write_text((ROOT / "airframes" / "quad_x.toml").read_text() + "\n[fc]\nmass = 1.3 # [kg] believed\n")
    ap = autopilot_factory(airframe=frame, params={"RP_EST_ORDER": 1, "RP_EST_WP": 5.0, "RP_COMP": 1})
    ap.vehicle.takeoff(timeout=15)
    time.sleep(2.0)
    while ap.vehicle.conn.recv_match(blocking=False) is not None:
        pass  # what queued during the sleep is 2 s old: read the estimate as it is now
    mass = ap.vehicle.wait("NAMED_VALUE_FLOAT", lambda m: m.name == "EXT_MASS", 2)
    force = ap.vehicle.wait("DEBUG_VECT", lambda m: m.name == "EXT_F", 2)
    assert abs(mass.value - 1.5) < 0.0075, mass
    assert abs(force.z - 0.2 * 9.81) < 0.02 and abs(force.x) < 0.01, force
    pos = ap.vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert abs(pos.z + 2.5) < 0.02, "compensation removes the sag of the unmodelled 0.2 kg"


@EXACT_STATE  # besides the rates, GPS_RAW_INT at home to 1e-7°: only the exact state's GPS is
def test_stream_rates_and_default_telemetry(vehicle):
    # Everything of PX4's GCS defaults arrives unasked.
    wanted = {"SYS_STATUS", "EXTENDED_SYS_STATE", "ATTITUDE", "LOCAL_POSITION_NED", "GLOBAL_POSITION_INT",
              "GPS_RAW_INT", "VFR_HUD", "HOME_POSITION", "BATTERY_STATUS", "SERVO_OUTPUT_RAW", "ACTUATOR_OUTPUT_STATUS",
              "MISSION_CURRENT"}
    seen = set()
    deadline = time.monotonic() + 3
    while time.monotonic() < deadline and not wanted <= seen:
        m = vehicle.conn.recv_match(blocking=True, timeout=0.5)
        if m is not None:
            seen.add(m.get_type())
    assert wanted <= seen, wanted - seen
    gps = vehicle.conn.messages["GPS_RAW_INT"]
    assert gps.fix_type == 3 and gps.lat == 473977420
    actuators = vehicle.conn.messages["ACTUATOR_OUTPUT_STATUS"]
    assert actuators.active == 4 and list(actuators.actuator) == [900.0] * 4 + [0.0] * 28, "disarmed: stopped (900 µs)"
    # LOCAL_POSITION_NED at 50 Hz instead of 1 Hz, then off.
    assert vehicle.command_ack(511, 32, 20000).result == ACCEPTED
    start, n = time.monotonic(), 0
    while time.monotonic() - start < 1.0:
        if vehicle.conn.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.2) is not None:
            n += 1
    assert 35 <= n <= 60, n
    assert vehicle.command_ack(510, 32).result == ACCEPTED
    assert vehicle.wait("MESSAGE_INTERVAL", lambda m: m.message_id == 32, 2).interval_us == 20000
    assert vehicle.command_ack(511, 32, -1).result == ACCEPTED
    time.sleep(0.2)
    with pytest.raises(gcs.LinkTimeout):
        vehicle.wait("LOCAL_POSITION_NED", timeout=1.5)  # the stream is off
    assert vehicle.command_ack(511, 9999, 1000).result == DENIED, "not a stream"
    # MAVProxy's REQUEST_DATA_STREAM(ALL, 4 Hz): ATTITUDE at 4 Hz.
    vehicle.conn.mav.request_data_stream_send(1, 1, 0, 4, 1)
    time.sleep(0.3)
    start, n = time.monotonic(), 0
    while time.monotonic() - start < 2.0:
        if vehicle.conn.recv_match(type="ATTITUDE", blocking=True, timeout=0.3) is not None:
            n += 1
    assert 6 <= n <= 12, n  # 8 expected; the socket may hold a few from before the window


def test_reposition_change_speed_and_set_home(vehicle):
    vehicle.takeoff()
    assert vehicle.command_ack(178, 1, 2.0).result == ACCEPTED
    assert vehicle.command_ack(178, 1, -3.0).result == DENIED
    # MAVSDK's goto_location: COMMAND_INT DO_REPOSITION, frame GLOBAL_INT (AMSL), 6 m north, 4 m above home,
    # with the mode-change flag (p2 = 1): flown in PX4's Goto mode (AUTO sub mode 21).
    lat = at(6, 0)[0]
    vehicle.conn.mav.command_int_send(1, 1, 5, 192, 0, 0, -1, 1, 0, NAN, lat, HOME_LON, 488.0 + 4.0)
    assert vehicle.wait("COMMAND_ACK", lambda m: m.command == 192, 2).result == ACCEPTED
    vehicle.wait_mode("GOTO", 2)
    vehicle.wait("LOCAL_POSITION_NED", lambda m: abs(m.x - 6) < 0.1 and abs(m.z + 4) < 0.1, 15,
                 what="the reposition target, held")
    # Home here; RTL now returns here (climbs to RTL_RETURN_ALT above it, then lands back).
    assert vehicle.command_ack(179, 1).result == ACCEPTED
    home = vehicle.wait("HOME_POSITION", lambda m: abs(m.x - 6) < 0.2, 3)
    assert abs(home.latitude - lat) < 0.3 * METRE_LAT and abs(home.z + 4) < 0.2
    # A reposition in a local frame is refused: UNSUPPORTED_MAV_FRAME (9).
    vehicle.conn.mav.command_int_send(1, 1, 1, 192, 0, 0, -1, 1, 0, NAN, 0, 0, -3.0)
    assert vehicle.wait("COMMAND_ACK", lambda m: m.command == 192, 2).result == 9


def test_params_file(tmp_path, autopilot_factory, rotorpilot):
    good = tmp_path / "vehicle.params"
    good.write_text("# Onboard parameters for Vehicle 1\n1\t1\tMIS_TAKEOFF_ALT\t4.000000\t9\nRP_CTRL 1\n")
    ap = autopilot_factory(args=["--params", str(good)])
    assert ap.vehicle.param_get("MIS_TAKEOFF_ALT") == 4.0 and ap.vehicle.param_get("RP_CTRL") == 1
    bad = tmp_path / "bad.params"
    bad.write_text("MIS_TAKEOFF_ALT 3\nRP_CTRL 7\n")
    proc = rotorpilot("run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0", "--params", bad,
                      "--duration", "5", timeout=30)
    assert proc.returncode == 2 and "bad.params:2" in proc.stderr and "RP_CTRL" in proc.stderr


def test_offboard_attitude_and_global_targets(vehicle):
    assert vehicle.command_ack(512, 148).result == ACCEPTED
    caps = vehicle.wait("AUTOPILOT_VERSION", timeout=2).capabilities
    for bit in (4, 8, 16, 32, 64, 128, 256, 8192):
        assert caps & bit, bit
    vehicle.takeoff()
    hover = 1.5 * 9.81 / (4 * 5.84e-6 * 1100.0 ** 2)
    roll = math.radians(10)
    q = [math.cos(roll / 2), math.sin(roll / 2), 0.0, 0.0]

    def stream_attitude(seconds, quat, mask=7, rates=(0, 0, 0)):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            vehicle.conn.mav.set_attitude_target_send(0, 1, 1, mask, quat, *rates, hover)
            vehicle.conn.recv_match(type="ATTITUDE", blocking=True, timeout=0.05)
        return vehicle.conn.messages["ATTITUDE"]

    stream_attitude(0.2, [1, 0, 0, 0])
    assert vehicle.command_ack(176, 1, 6, 0).result == ACCEPTED
    att = stream_attitude(1.5, q)
    assert abs(att.roll - roll) < 0.01 and abs(att.pitch) < 0.01, att
    # Rates + thrust (mask 128): yaw at 0.5 rad/s.
    att = stream_attitude(1.0, [1, 0, 0, 0], mask=128, rates=(0, 0, 0.5))
    assert abs(att.yawspeed - 0.5) < 0.05, att
    # SET_POSITION_TARGET_GLOBAL_INT: 3 m north of home, 3 m above it.
    # The attitude phase left the vehicle drifting; it arrives through the offboard limits
    # (MPC_ACC_HOR 3 m/s²) within seconds, however loaded the machine is.
    lat = at(3, 0)[0]
    end = time.monotonic() + 15

    def arrived(p):
        return abs(p.x - 3) < 0.1 and abs(p.y) < 0.1 and abs(p.z + 3) < 0.1

    pos = None
    while time.monotonic() < end and not (pos is not None and arrived(pos)):
        vehicle.conn.mav.set_position_target_global_int_send(0, 1, 1, 6, 2552, lat, HOME_LON, 3.0, 0, 0, 0, 0, 0, 0,
                                                             0, 0)
        pos = vehicle.conn.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.05) or pos
    assert pos is not None and arrived(pos), pos


@EXACT_STATE  # HIGHRES_IMU against gravity to 0.05 m/s²: the exact specific force, not a real IMU's
def test_highres_imu_and_ground_effect_switch(vehicle):
    assert vehicle.command_ack(511, 105, 100000).result == ACCEPTED
    imu = vehicle.wait("HIGHRES_IMU", timeout=2)
    assert abs(imu.zacc + 9.81) < 0.05 and abs(imu.abs_pressure - 955.0) < 5.0, imu
    for value in (0, 1):
        vehicle.conn.mav.param_set_send(1, 1, b"RP_GND_EFFECT", int32_bits(value), 6)
        echo = vehicle.wait("PARAM_VALUE", lambda m: m.param_id == "RP_GND_EFFECT", 2)
        assert float_bits_to_int(echo.param_value) == value


@EXACT_STATE  # the flight against the plan to 0.1 m and landed within 0.2 m of home: the GPS wanders more
def test_full_flight_takeoff_offboard_square_mission_rtl_land(autopilot):
    """The issue's end-to-end flight: arm → take-off → offboard square → 4-waypoint mission →
    RTL → land → auto-disarm, positions checked against the plan."""
    plan = [(4, 0), (4, 4), (0, 4), (0, 0)]
    autopilot.vehicle.upload_mission(square_mission(plan))
    autopilot.vehicle.param_set("RTL_RETURN_ALT", 4.0)
    # No cone: the mission ends over home, where PX4's cone would land at once (RTL_CONE_ANG 45).
    autopilot.vehicle.param_set("RTL_CONE_ANG", 0)
    autopilot.vehicle.takeoff()

    hold_setpoint(autopilot, 0, 0, -2.5, 0.3)
    assert autopilot.vehicle.command_ack(176, 1, 6, 0).result == ACCEPTED
    for x, y in [(2, 0), (2, 2), (0, 2), (0, 0)]:
        pos = hold_setpoint(autopilot, x, y, -2.5, 3.0)
        assert math.hypot(pos.x - x, pos.y - y) < 0.1 and abs(pos.z + 2.5) < 0.1, (x, y, pos)

    assert autopilot.vehicle.command_ack(176, 1, 4, 4).result == ACCEPTED
    autopilot.vehicle.stop_setpoints()
    reached, checked = follow_mission(autopilot, plan, 0, 5, 40)
    assert reached == [0, 1, 2, 3, 4] and len(checked) >= 3
    autopilot.vehicle.wait("GLOBAL_POSITION_INT", lambda m: m.relative_alt > 3900, 10,
                           what="the RTL climb to RTL_RETURN_ALT")
    autopilot.vehicle.wait("STATUSTEXT", lambda m: "Disarmed" in m.text, 30)
    pos = autopilot.vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert math.hypot(pos.x, pos.y) < 0.2 and abs(pos.z) < 0.2, "landed at home"
    autopilot.vehicle.wait_disarmed(2)
