"""`rotorpilot run` driven over MAVLink by pymavlink: heartbeat, command/ACK rules, modes,
take-off → hold → land → auto-disarm. Ports are all ephemeral (port 0)."""
import json
import math
import os
import pathlib
import subprocess
import time

import pytest

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = pathlib.Path(os.environ.get("ROTORPILOT_BIN", ROOT / "target" / "release" / "rotorpilot"))
NAN = float("nan")
ACCEPTED, TEMPORARILY_REJECTED, DENIED, UNSUPPORTED = 0, 1, 2, 3
# One-shot messages (events and replies) that `Autopilot.command` keeps for `wait` when they arrive
# before the ACK; periodic telemetry is not kept (the next one is fresher).
ONE_SHOT = {"STATUSTEXT", "MISSION_ITEM_REACHED", "PARAM_VALUE", "AUTOPILOT_VERSION", "MESSAGE_INTERVAL"}
PENDING_MAX = 100


class Autopilot:
    """A running `rotorpilot run` with a pymavlink GCS connection on an ephemeral port."""

    def __init__(self, *args):
        self.gcs = mavutil.mavlink_connection("udpin:127.0.0.1:0", source_system=255, source_component=190)
        port = self.gcs.port.getsockname()[1]
        self.started = time.monotonic()
        self.proc = subprocess.Popen(
            [str(BINARY), "run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0",
             "--gcs", f"127.0.0.1:{port}", "--api", "127.0.0.1:9", "--duration", "120", *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = json.loads(self.proc.stdout.readline())
        self.pending = []

    def heartbeat(self, timeout=5):
        hb = self.gcs.recv_match(type="HEARTBEAT", blocking=True, timeout=timeout)
        assert hb is not None, "no HEARTBEAT"
        return hb

    def command(self, command, *params, target=(1, 1)):
        """COMMAND_LONG; returns the COMMAND_ACK for it (within the 0.5 s budget of docs/mavlink.md §3.1).
        One-shot messages arriving meanwhile are kept for `wait` (a STATUSTEXT may overtake the ACK)."""
        p = list(params) + [NAN] * (7 - len(params))
        self.gcs.mav.command_long_send(target[0], target[1], command, 0, *p)
        deadline = time.monotonic() + 0.5
        while time.monotonic() < deadline:
            m = self.gcs.recv_match(blocking=True, timeout=max(0.0, deadline - time.monotonic()))
            if m is None:
                continue
            if m.get_type() == "COMMAND_ACK" and m.command == command:
                return m
            if m.get_type() in ONE_SHOT:
                self.pending = (self.pending + [m])[-PENDING_MAX:]
        return None

    def take_off(self, timeout=10):
        """NAV_TAKEOFF and arm, both ACCEPTED, then in the air (EXTENDED_SYS_STATE) within `timeout`."""
        assert self.command(22).result == ACCEPTED
        assert self.command(400, 1.0).result == ACCEPTED
        assert self.wait(lambda m: m.landed_state == 2, "EXTENDED_SYS_STATE", timeout) is not None, "in the air"

    def wait(self, predicate, types, timeout):
        """The first message of `types` (a name or a list) satisfying `predicate` within `timeout`,
        looking first at the one-shot messages `command` kept."""
        names = [types] if isinstance(types, str) else list(types)
        for i, m in enumerate(self.pending):
            if m.get_type() in names and predicate(m):
                del self.pending[: i + 1]
                return m
        self.pending = []
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.gcs.recv_match(type=types, blocking=True, timeout=0.5)
            if m is not None and predicate(m):
                return m
        return None

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
        code = self.proc.wait(timeout=10)
        self.gcs.close()
        return code


@pytest.fixture
def autopilot(rotorpilot_bin):
    ap = Autopilot()
    yield ap
    ap.close()


def test_ready_line_and_first_heartbeat(autopilot):
    assert autopilot.ready["event"] == "ready" and autopilot.ready["sysid"] == 1
    assert autopilot.ready["gcs_bind"].startswith("127.0.0.1:") and not autopilot.ready["gcs_bind"].endswith(":0")
    hb = autopilot.heartbeat()
    assert hb.get_srcSystem() == 1 and hb.get_srcComponent() == 1
    assert hb.autopilot == mavutil.mavlink.MAV_AUTOPILOT_PX4 and hb.type == mavutil.mavlink.MAV_TYPE_QUADROTOR
    assert hb.base_mode & 1 and not hb.base_mode & 128
    assert hb.custom_mode == (4 << 16) | (3 << 24), "AUTO.LOITER"


def test_command_rules(autopilot):
    autopilot.heartbeat()
    autopilot.gcs.mav.heartbeat_send(6, 8, 0, 0, 0)
    assert autopilot.command(31999).result == UNSUPPORTED, "ids the crate does not know"
    assert autopilot.command(mavutil.mavlink.MAV_CMD_DO_SET_SERVO, 1, 1500).result == UNSUPPORTED
    ack = autopilot.command(400, 2.0)
    assert ack.result == DENIED and (ack.target_system, ack.target_component) == (255, 190)
    text = autopilot.wait(lambda m: True, "STATUSTEXT", 2)
    assert text is not None and "param1" in text.text
    assert autopilot.command(400, 1.0, target=(7, 1)) is None, "other systems' commands are ignored"
    assert autopilot.command(176, 1, 1, 0).result == TEMPORARILY_REJECTED, "MANUAL needs sticks"
    assert autopilot.command(176, 1, 4, 12).result == DENIED
    assert autopilot.command(176, 1, 4, 4).result == TEMPORARILY_REJECTED, "no mission"
    assert autopilot.command(176, 1, 3, 0, target=(0, 0)).result == ACCEPTED
    hb = autopilot.wait(lambda m: m.custom_mode == 3 << 16, "HEARTBEAT", 2)
    assert hb is not None, "POSCTL shows in the next heartbeat"
    # SET_MODE (#11), QGC's way: no ACK, the heartbeat confirms.
    autopilot.gcs.mav.set_mode_send(1, 1, (4 << 16) | (3 << 24))
    assert autopilot.wait(lambda m: m.custom_mode == (4 << 16) | (3 << 24), "HEARTBEAT", 2) is not None
    # DO_SET_STANDARD_MODE (262): POSITION_HOLD → POSCTL; ORBIT needs the air; CRUISE is not
    # available → FAILED.
    assert autopilot.command(262, 1).result == ACCEPTED
    assert autopilot.wait(lambda m: m.custom_mode == 3 << 16, "HEARTBEAT", 2) is not None
    assert autopilot.command(262, 2).result == 1  # MAV_RESULT_TEMPORARILY_REJECTED
    text = autopilot.wait(lambda m: True, "STATUSTEXT", 2)
    assert text is not None and text.text == "Mode ORBIT: not in the air"
    assert autopilot.command(262, 3).result == 4  # MAV_RESULT_FAILED
    text = autopilot.wait(lambda m: True, "STATUSTEXT", 2)
    assert text is not None and "Standard mode 3" in text.text


def test_takeoff_hold_land_and_auto_disarm(autopilot):
    autopilot.heartbeat()
    assert autopilot.command(22).result == ACCEPTED, "NAV_TAKEOFF while disarmed (PX4)"
    assert autopilot.command(400, 1.0).result == ACCEPTED
    armed = autopilot.wait(lambda m: m.base_mode & 128, "HEARTBEAT", 2)
    assert armed is not None and armed.system_status == 4
    in_air = autopilot.wait(lambda m: m.landed_state == 2, "EXTENDED_SYS_STATE", 10)
    assert in_air is not None, "take-off completes"
    pos = autopilot.wait(lambda m: True, "LOCAL_POSITION_NED", 3)
    assert abs(pos.z + 2.5) < 0.05 and math.hypot(pos.x, pos.y) < 0.05, "MIS_TAKEOFF_ALT above home"
    glob = autopilot.wait(lambda m: True, "GLOBAL_POSITION_INT", 3)
    assert abs(glob.relative_alt - 2500) < 50 and abs(glob.alt - 490_500) < 50
    assert autopilot.command(400, 0.0).result == TEMPORARILY_REJECTED, "no disarm in the air"
    assert autopilot.command(21).result == ACCEPTED
    disarmed = autopilot.wait(lambda m: "Disarmed" in m.text, "STATUSTEXT", 15)
    assert disarmed is not None
    hb = autopilot.wait(lambda m: not m.base_mode & 128, "HEARTBEAT", 3)
    assert hb is not None and hb.system_status == 3
    on_ground = autopilot.wait(lambda m: m.landed_state == 1, "EXTENDED_SYS_STATE", 3)
    assert on_ground is not None


def test_sigterm_stops_cleanly(autopilot):
    autopilot.heartbeat()
    autopilot.proc.terminate()
    assert autopilot.proc.wait(timeout=10) == 0
    assert "stopped after" in autopilot.proc.stderr.read()


def test_discovery_services(autopilot):
    autopilot.heartbeat()
    assert autopilot.command(512, 148).result == ACCEPTED
    version = autopilot.wait(lambda m: True, "AUTOPILOT_VERSION", 2)
    assert version is not None and version.capabilities & 8192, "MAVLINK2"
    assert autopilot.command(520).result == ACCEPTED
    assert autopilot.wait(lambda m: True, "AUTOPILOT_VERSION", 2) is not None
    assert autopilot.command(410).result == ACCEPTED
    home = autopilot.wait(lambda m: True, "HOME_POSITION", 2)
    assert home is not None and (home.latitude, home.longitude, home.altitude) == (473977420, 85455940, 488000)
    assert autopilot.command(512, 435, 1).result == ACCEPTED, "AVAILABLE_MODES"
    assert autopilot.command(512, 999).result == DENIED, "a message that is not produced"
    autopilot.gcs.mav.ping_send(123456, 9, 0, 0)
    ping = autopilot.wait(lambda m: m.seq == 9, "PING", 2)
    assert ping is not None and ping.time_usec == 123456 and ping.target_system == 255
    autopilot.gcs.mav.timesync_send(0, 777)
    sync = autopilot.wait(lambda m: m.ts1 == 777, "TIMESYNC", 2)
    assert sync is not None and sync.tc1 > 0
    payload = [0] * 251
    payload[0:2] = [5, 0]
    payload[3] = 4  # OpenFileRO
    autopilot.gcs.mav.file_transfer_protocol_send(0, 1, 1, payload)
    ftp = autopilot.wait(lambda m: True, "FILE_TRANSFER_PROTOCOL", 2)
    assert ftp is not None and list(ftp.payload[:6]) == [6, 0, 0, 129, 1, 4] and ftp.payload[12] == 10


def test_duplicates_and_command_int(autopilot):
    autopilot.heartbeat()
    first = autopilot.command(176, 1, 3, 0)
    again = autopilot.command(176, 1, 3, 0)
    assert first.result == again.result == ACCEPTED, "a retransmission gets the cached result"
    # COMMAND_INT NAV_TAKEOFF with z AMSL 493 m = 5 m above home.
    autopilot.gcs.mav.command_int_send(1, 1, 0, 22, 0, 0, NAN, 0, 0, NAN, 2147483647, 2147483647, 493.0)
    ack = autopilot.wait(lambda m: m.command == 22, "COMMAND_ACK", 2)
    assert ack is not None and ack.result == ACCEPTED
    assert autopilot.command(400, 1.0).result == ACCEPTED
    pos = autopilot.wait(lambda m: abs(m.z + 5.0) < 0.05, "LOCAL_POSITION_NED", 12)
    assert pos is not None, "climbed to 5 m above home"


def int32_bits(value):
    """Byte-wise INT32 in the float field (docs/mavlink.md §8.2)."""
    import struct
    return struct.unpack("<f", struct.pack("<i", value))[0]


def float_bits_to_int(value):
    import struct
    return struct.unpack("<i", struct.pack("<f", value))[0]


def test_parameter_protocol(autopilot):
    autopilot.heartbeat()
    autopilot.gcs.mav.param_request_list_send(1, 1)
    values = {}
    hashes = []
    deadline = time.monotonic() + 5
    count = None
    while time.monotonic() < deadline and (count is None or len(values) < count):
        m = autopilot.gcs.recv_match(type="PARAM_VALUE", blocking=True, timeout=1)
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
    autopilot.gcs.mav.param_request_read_send(1, 1, b"", index)
    by_index = autopilot.wait(lambda m: m.param_index == index, "PARAM_VALUE", 2)
    assert by_index is not None and by_index.param_id == "RP_GEO_KP_Z"
    # fsr gains scaled to quad_x keep K_p (mass 1.5 kg on both).
    assert by_index.param_value == 25.0

    autopilot.gcs.mav.param_set_send(1, 1, b"MIS_TAKEOFF_ALT", 4.0, 9)
    echo = autopilot.wait(lambda m: m.param_id == "MIS_TAKEOFF_ALT", "PARAM_VALUE", 2)
    assert echo is not None and echo.param_value == 4.0
    autopilot.gcs.mav.param_set_send(1, 1, b"RP_CTRL", int32_bits(5), 6)
    echo = autopilot.wait(lambda m: m.param_id == "RP_CTRL", "PARAM_VALUE", 2)
    assert echo is not None and float_bits_to_int(echo.param_value) == 0, "refused: unchanged value echoed"
    text = autopilot.wait(lambda m: "RP_CTRL" in m.text, "STATUSTEXT", 2)
    assert text is not None
    autopilot.gcs.mav.param_set_send(1, 1, b"NO_SUCH_PARAM", 1.0, 9)
    # PARAM_ERROR (345) is newer than pymavlink's dialect; the STATUSTEXT says it too.
    assert autopilot.wait(lambda m: "NO_SUCH_PARAM" in m.text, "STATUSTEXT", 2) is not None

    # The new take-off altitude is used.
    assert autopilot.command(22).result == ACCEPTED
    assert autopilot.command(400, 1.0).result == ACCEPTED
    pos = autopilot.wait(lambda m: abs(m.z + 4.0) < 0.05, "LOCAL_POSITION_NED", 12)
    assert pos is not None


def test_controller_and_estimator_switch_in_flight(autopilot):
    autopilot.heartbeat()
    autopilot.take_off()
    for name, value in [(b"RP_CTRL", 2), (b"RP_EST_ORDER", 1), (b"RP_COMP", 1), (b"RP_CTRL", 1)]:
        autopilot.gcs.mav.param_set_send(1, 1, name, int32_bits(value), 6)
        echo = autopilot.wait(lambda m: m.param_id == name.decode(), "PARAM_VALUE", 2)
        assert echo is not None and float_bits_to_int(echo.param_value) == value
        # Bumpless: the hover stays within 5 cm while the law or the estimator changes.
        end = time.monotonic() + 1.5
        while time.monotonic() < end:
            m = autopilot.gcs.recv_match(type="ATTITUDE", blocking=True, timeout=1)
            pos = autopilot.gcs.messages.get("LOCAL_POSITION_NED")
            if pos is not None:
                assert abs(pos.z + 2.5) < 0.05 and math.hypot(pos.x, pos.y) < 0.05, (name, pos)
            assert m is None or abs(m.roll) < 0.05


def stream_position(autopilot, x, y, z, seconds, mask=2552):
    """Streams a LOCAL_NED position setpoint at 20 Hz for `seconds`; returns the last LOCAL_POSITION_NED."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        autopilot.gcs.mav.set_position_target_local_ned_send(0, 1, 1, 1, mask, x, y, z, 0, 0, 0, 0, 0, 0, 0, 0)
        autopilot.gcs.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.05)
    return autopilot.gcs.messages.get("LOCAL_POSITION_NED")


def test_offboard_square_and_setpoint_loss(autopilot):
    autopilot.heartbeat()
    autopilot.take_off()
    assert autopilot.command(176, 1, 6, 0).result == TEMPORARILY_REJECTED, "no setpoint stream yet"
    stream_position(autopilot, 0, 0, -2.5, 0.3)
    autopilot.gcs.mav.set_position_target_local_ned_send(0, 1, 1, 1, 2552, 0, 0, -2.5, 0, 0, 0, 0, 0, 0, 0, 0)
    assert autopilot.command(176, 1, 6, 0).result == ACCEPTED
    assert autopilot.wait(lambda m: m.custom_mode == 6 << 16, "HEARTBEAT", 2) is not None
    for x, y in [(2, 0), (2, 2), (0, 2), (0, 0)]:
        pos = stream_position(autopilot, x, y, -2.5, 4.0)
        assert math.hypot(pos.x - x, pos.y - y) < 0.1 and abs(pos.z + 2.5) < 0.1, (x, y, pos)
    # A refused setpoint (force bit) says why.
    autopilot.gcs.mav.set_position_target_local_ned_send(0, 1, 1, 1, 2552 | 512, 0, 0, -2.5, 0, 0, 0, 0, 0, 0, 0, 0)
    assert autopilot.wait(lambda m: "force" in m.text, "STATUSTEXT", 2) is not None
    # Stop streaming: after COM_OF_LOSS_T the vehicle holds position in POSCTL.
    lost = autopilot.wait(lambda m: "Offboard lost" in m.text, "STATUSTEXT", 3)
    assert lost is not None
    assert autopilot.wait(lambda m: m.custom_mode == 3 << 16, "HEARTBEAT", 2) is not None
    time.sleep(1.0)
    pos = autopilot.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
    assert math.hypot(pos.x, pos.y) < 0.1 and abs(pos.z + 2.5) < 0.1


def test_offboard_body_frame_velocity(autopilot):
    autopilot.heartbeat()
    autopilot.command(22)
    autopilot.command(400, 1.0)
    assert autopilot.wait(lambda m: m.landed_state == 2, "EXTENDED_SYS_STATE", 10) is not None
    start = autopilot.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
    autopilot.gcs.mav.set_position_target_local_ned_send(0, 1, 1, 8, 1479, 0, 0, 0, 1.0, 0, 0, 0, 0, 0, 0, 0)
    assert autopilot.command(176, 1, 6, 0).result == ACCEPTED
    end = time.monotonic() + 8.0
    pos = start
    while time.monotonic() < end and pos.x - start.x < 2.0:
        # MAVSDK's body-frame velocity: 1 m/s forward (heading 0 → north), no yaw rate.
        autopilot.gcs.mav.set_position_target_local_ned_send(0, 1, 1, 8, 1479, 0, 0, 0, 1.0, 0, 0, 0, 0, 0, 0, 0)
        autopilot.gcs.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.05)
        pos = autopilot.gcs.messages["LOCAL_POSITION_NED"]
    assert pos.x - start.x >= 2.0, "flew forward"
    assert abs(pos.vx - 1.0) < 0.1 and abs(pos.vy) < 0.1 and abs(pos.y - start.y) < 0.1


HOME_LAT, HOME_LON = 473977420, 85455940
METRE_LAT = 1e7 / (6371000 * math.pi / 180)  # degE7 per metre north
METRE_LON = METRE_LAT / math.cos(math.radians(47.397742))  # degE7 per metre east at home


def north(metres):
    """degE7 latitude `metres` north of home."""
    return HOME_LAT + round(metres * METRE_LAT)


def east(metres):
    """degE7 longitude `metres` east of home."""
    return HOME_LON + round(metres * METRE_LON)


def follow_mission(autopilot, waypoints, first_seq, count, timeout):
    """Collects MISSION_ITEM_REACHED until `count` items are reached; the first GLOBAL_POSITION_INT
    after reaching waypoint item `first_seq + i` (GLOBAL_POSITION_INT streams at 5 Hz) must be
    within 0.6 m of `waypoints[i]` (north, east) at 3 m. Returns (reached, checked)."""
    reached, checked = [], []
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and len(reached) < count:
        m = autopilot.gcs.recv_match(type=["MISSION_ITEM_REACHED", "GLOBAL_POSITION_INT"], blocking=True, timeout=1)
        if m is None:
            continue
        if m.get_type() == "MISSION_ITEM_REACHED":
            reached.append(m.seq)
        elif reached and 0 <= reached[-1] - first_seq < len(waypoints) and reached[-1] not in checked:
            x, y = waypoints[reached[-1] - first_seq]
            assert abs(m.lat - north(x)) < 0.6 * METRE_LAT and abs(m.lon - east(y)) < 0.6 * METRE_LON, m
            assert abs(m.relative_alt - 3000) < 300
            checked.append(reached[-1])
    return reached, checked


def upload(autopilot, items):
    """Uploads (command, x_degE7, y_degE7, z, p1) items in GLOBAL_RELATIVE_ALT_INT; returns the MISSION_ACK type."""
    autopilot.gcs.mav.mission_count_send(1, 1, len(items), 0)
    while True:
        m = autopilot.gcs.recv_match(type=["MISSION_REQUEST_INT", "MISSION_ACK"], blocking=True, timeout=3)
        assert m is not None, "vehicle stopped asking"
        if m.get_type() == "MISSION_ACK":
            return m.type
        command, x, y, z, p1 = items[m.seq]
        autopilot.gcs.mav.mission_item_int_send(1, 1, m.seq, 6, command, 0, 1, p1, 0, 0, NAN, x, y, z, 0)


def download(autopilot):
    autopilot.gcs.mav.mission_request_list_send(1, 1, 0)
    count = autopilot.wait(lambda m: True, "MISSION_COUNT", 2).count
    items = []
    for seq in range(count):
        autopilot.gcs.mav.mission_request_int_send(1, 1, seq, 0)
        items.append(autopilot.wait(lambda m, s=seq: m.seq == s, "MISSION_ITEM_INT", 2))
    return items


def test_mission_upload_download_fly_and_return(autopilot):
    autopilot.heartbeat()
    assert autopilot.command(176, 1, 4, 4).result == TEMPORARILY_REJECTED, "no mission yet"
    square = [(22, HOME_LAT, HOME_LON, 3.0, 0)] + [
        (16, north(x), east(y), 3.0, 0.0) for x, y in [(5, 0), (5, 5), (0, 5), (0, 0)]
    ] + [(20, 0, 0, 0.0, 0)]
    assert upload(autopilot, square) == 0
    got = download(autopilot)
    assert [m.command for m in got] == [22, 16, 16, 16, 16, 20] and got[2].x == north(5)
    # A bad mission is refused with the item's result and leaves the stored one unchanged.
    assert upload(autopilot, square[:2] + [(31000, 0, 0, 0.0, 0)]) == 3, "UNSUPPORTED"
    assert len(download(autopilot)) == 6
    current = autopilot.wait(lambda m: True, "MISSION_CURRENT", 3)
    assert current.total == 6 and current.mission_state == 2, "NOT_STARTED"

    autopilot.gcs.mav.param_set_send(1, 1, b"RTL_RETURN_ALT", 5.0, 9)
    assert autopilot.wait(lambda m: m.param_id == "RTL_RETURN_ALT", "PARAM_VALUE", 2).param_value == 5.0
    assert autopilot.command(176, 1, 4, 4).result == ACCEPTED
    assert autopilot.command(400, 1.0).result == ACCEPTED
    reached, checked = follow_mission(autopilot, [(5, 0), (5, 5), (0, 5), (0, 0)], 1, 6, 60)
    assert reached == [0, 1, 2, 3, 4, 5]
    assert len(checked) >= 3
    rtl = autopilot.wait(lambda m: m.custom_mode == (4 << 16) | (5 << 24), "HEARTBEAT", 3)
    assert rtl is not None, "the RTL item switches to AUTO.RTL"
    assert autopilot.wait(lambda m: "Disarmed" in m.text, "STATUSTEXT", 40) is not None
    pos = autopilot.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
    assert math.hypot(pos.x, pos.y) < 0.2 and abs(pos.z) < 0.2, "landed at home"


def test_live_wrench_estimate(tmp_path, rotorpilot_bin):
    """The estimator's external force and mass estimate stream on DEBUG_VECT / NAMED_VALUE_FLOAT."""
    frame = tmp_path / "heavy.toml"
    frame.write_text((ROOT / "airframes" / "quad_x.toml").read_text() + "\n[fc]\nmass = 1.3 # [kg] believed\n")
    ap = Autopilot("--airframe", str(frame))
    try:
        ap.heartbeat()
        for name, value in [(b"RP_EST_ORDER", 1), (b"RP_EST_WP", None), (b"RP_COMP", 1)]:
            if value is None:
                ap.gcs.mav.param_set_send(1, 1, name, 5.0, 9)
            else:
                ap.gcs.mav.param_set_send(1, 1, name, int32_bits(value), 6)
            assert ap.wait(lambda m: m.param_id == name.decode(), "PARAM_VALUE", 2) is not None
        ap.take_off(timeout=15)
        time.sleep(2.0)
        while ap.gcs.recv_match(blocking=False) is not None:
            pass  # what queued during the sleep is 2 s old: read the estimate as it is now
        mass = ap.wait(lambda m: m.name == "EXT_MASS", "NAMED_VALUE_FLOAT", 2)
        force = ap.wait(lambda m: m.name == "EXT_F", "DEBUG_VECT", 2)
        assert mass is not None and abs(mass.value - 1.5) < 0.0075, mass
        assert force is not None and abs(force.z - 0.2 * 9.81) < 0.02 and abs(force.x) < 0.01, force
        pos = ap.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
        assert abs(pos.z + 2.5) < 0.02, "compensation removes the sag of the unmodelled 0.2 kg"
    finally:
        ap.close()


def test_stream_rates_and_default_telemetry(autopilot):
    autopilot.heartbeat()
    autopilot.gcs.mav.heartbeat_send(6, 8, 0, 0, 0)
    # Everything of PX4's GCS defaults arrives unasked.
    wanted = {"SYS_STATUS", "EXTENDED_SYS_STATE", "ATTITUDE", "LOCAL_POSITION_NED", "GLOBAL_POSITION_INT",
              "GPS_RAW_INT", "VFR_HUD", "HOME_POSITION", "BATTERY_STATUS", "SERVO_OUTPUT_RAW", "ACTUATOR_OUTPUT_STATUS",
              "MISSION_CURRENT"}
    seen = set()
    deadline = time.monotonic() + 3
    while time.monotonic() < deadline and not wanted <= seen:
        m = autopilot.gcs.recv_match(blocking=True, timeout=0.5)
        if m is not None:
            seen.add(m.get_type())
    assert wanted <= seen, wanted - seen
    gps = autopilot.gcs.messages["GPS_RAW_INT"]
    assert gps.fix_type == 3 and gps.lat == 473977420
    actuators = autopilot.gcs.messages["ACTUATOR_OUTPUT_STATUS"]
    assert actuators.active == 4 and list(actuators.actuator) == [0.0] * 32, "disarmed: rotors stopped"
    # LOCAL_POSITION_NED at 50 Hz instead of 1 Hz, then off.
    assert autopilot.command(511, 32, 20000).result == ACCEPTED
    start, n = time.monotonic(), 0
    while time.monotonic() - start < 1.0:
        if autopilot.gcs.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.2) is not None:
            n += 1
    assert 35 <= n <= 60, n
    assert autopilot.command(510, 32).result == ACCEPTED
    interval = autopilot.wait(lambda m: m.message_id == 32, "MESSAGE_INTERVAL", 2)
    assert interval is not None and interval.interval_us == 20000
    assert autopilot.command(511, 32, -1).result == ACCEPTED
    time.sleep(0.2)
    assert autopilot.wait(lambda m: True, "LOCAL_POSITION_NED", 1.5) is None, "stream off"
    assert autopilot.command(511, 9999, 1000).result == DENIED, "not a stream"
    # MAVProxy's REQUEST_DATA_STREAM(ALL, 4 Hz): ATTITUDE at 4 Hz.
    autopilot.gcs.mav.request_data_stream_send(1, 1, 0, 4, 1)
    time.sleep(0.3)
    start, n = time.monotonic(), 0
    while time.monotonic() - start < 2.0:
        if autopilot.gcs.recv_match(type="ATTITUDE", blocking=True, timeout=0.3) is not None:
            n += 1
    assert 6 <= n <= 12, n  # 8 expected; the socket may hold a few from before the window


def test_reposition_change_speed_and_set_home(autopilot):
    autopilot.heartbeat()
    autopilot.take_off()
    assert autopilot.command(178, 1, 2.0).result == ACCEPTED
    assert autopilot.command(178, 1, -3.0).result == DENIED
    # MAVSDK's goto_location: COMMAND_INT DO_REPOSITION, frame GLOBAL_INT (AMSL), 6 m north, 4 m above home.
    lat = HOME_LAT + round(6 * METRE_LAT)
    autopilot.gcs.mav.command_int_send(1, 1, 5, 192, 0, 0, -1, 1, 0, NAN, lat, HOME_LON, 488.0 + 4.0)
    ack = autopilot.wait(lambda m: m.command == 192, "COMMAND_ACK", 2)
    assert ack is not None and ack.result == ACCEPTED
    assert autopilot.wait(lambda m: m.custom_mode == (4 << 16) | (3 << 24), "HEARTBEAT", 2) is not None
    pos = autopilot.wait(lambda m: abs(m.x - 6) < 0.1 and abs(m.z + 4) < 0.1, "LOCAL_POSITION_NED", 15)
    assert pos is not None, "flew to the reposition target and holds there"
    # Home here; RTL now returns here (climbs to RTL_RETURN_ALT above it, then lands back).
    assert autopilot.command(179, 1).result == ACCEPTED
    home = autopilot.wait(lambda m: abs(m.x - 6) < 0.2, "HOME_POSITION", 3)
    assert home is not None and abs(home.latitude - lat) < 0.3 * METRE_LAT and abs(home.z + 4) < 0.2
    # A reposition in a local frame is refused: UNSUPPORTED_MAV_FRAME (9).
    autopilot.gcs.mav.command_int_send(1, 1, 1, 192, 0, 0, -1, 1, 0, NAN, 0, 0, -3.0)
    ack = autopilot.wait(lambda m: m.command == 192, "COMMAND_ACK", 2)
    assert ack is not None and ack.result == 9


def test_params_file(tmp_path, rotorpilot_bin):
    good = tmp_path / "vehicle.params"
    good.write_text("# Onboard parameters for Vehicle 1\n1\t1\tMIS_TAKEOFF_ALT\t4.000000\t9\nRP_CTRL 1\n")
    ap = Autopilot("--params", str(good))
    try:
        ap.heartbeat()
        for name, check in [(b"MIS_TAKEOFF_ALT", lambda v: v.param_value == 4.0),
                            (b"RP_CTRL", lambda v: float_bits_to_int(v.param_value) == 1)]:
            ap.gcs.mav.param_request_read_send(1, 1, name, -1)
            value = ap.wait(lambda m: m.param_id == name.decode(), "PARAM_VALUE", 2)
            assert value is not None and check(value)
    finally:
        ap.close()
    bad = tmp_path / "bad.params"
    bad.write_text("MIS_TAKEOFF_ALT 3\nRP_CTRL 7\n")
    proc = subprocess.run([str(BINARY), "run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0",
                           "--params", str(bad), "--duration", "5"], capture_output=True, text=True, timeout=30)
    assert proc.returncode == 2 and "bad.params:2" in proc.stderr and "RP_CTRL" in proc.stderr


def test_gcs_link_loss_returns_to_launch(autopilot):
    autopilot.heartbeat()
    for name, value in [(b"NAV_DLL_ACT", 2), (b"COM_DL_LOSS_T", 5)]:
        autopilot.gcs.mav.param_set_send(1, 1, name, int32_bits(value), 6)
        assert autopilot.wait(lambda m: m.param_id == name.decode(), "PARAM_VALUE", 2) is not None
    autopilot.gcs.mav.heartbeat_send(6, 8, 0, 0, 0)  # one GCS heartbeat, then silence
    assert autopilot.command(22).result == ACCEPTED
    assert autopilot.command(400, 1.0).result == ACCEPTED
    lost = autopilot.wait(lambda m: "link lost" in m.text, "STATUSTEXT", 9)
    assert lost is not None and "returning" in lost.text
    assert autopilot.wait(lambda m: m.custom_mode == (4 << 16) | (5 << 24), "HEARTBEAT", 2) is not None


def test_offboard_attitude_and_global_targets(autopilot):
    autopilot.heartbeat()
    assert autopilot.command(512, 148).result == ACCEPTED
    caps = autopilot.wait(lambda m: True, "AUTOPILOT_VERSION", 2).capabilities
    for bit in (4, 8, 16, 32, 64, 128, 256, 8192):
        assert caps & bit, bit
    autopilot.take_off()
    hover = 1.5 * 9.81 / (4 * 5.84e-6 * 1100.0 ** 2)
    roll = math.radians(10)
    q = [math.cos(roll / 2), math.sin(roll / 2), 0.0, 0.0]

    def stream_attitude(seconds, quat, mask=7, rates=(0, 0, 0)):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            autopilot.gcs.mav.set_attitude_target_send(0, 1, 1, mask, quat, *rates, hover)
            autopilot.gcs.recv_match(type="ATTITUDE", blocking=True, timeout=0.05)
        return autopilot.gcs.messages["ATTITUDE"]

    stream_attitude(0.2, [1, 0, 0, 0])
    assert autopilot.command(176, 1, 6, 0).result == ACCEPTED
    att = stream_attitude(1.5, q)
    assert abs(att.roll - roll) < 0.01 and abs(att.pitch) < 0.01, att
    # Rates + thrust (mask 128): yaw at 0.5 rad/s.
    att = stream_attitude(1.0, [1, 0, 0, 0], mask=128, rates=(0, 0, 0.5))
    assert abs(att.yawspeed - 0.5) < 0.05, att
    # SET_POSITION_TARGET_GLOBAL_INT: 3 m north of home, 3 m above it.
    # The attitude phase left the vehicle drifting; it arrives through the offboard limits
    # (MPC_ACC_HOR 3 m/s²) within seconds, however loaded the machine is.
    lat = HOME_LAT + round(3 * METRE_LAT)
    end = time.monotonic() + 15

    def arrived(p):
        return abs(p.x - 3) < 0.1 and abs(p.y) < 0.1 and abs(p.z + 3) < 0.1

    pos = None
    while time.monotonic() < end and not (pos is not None and arrived(pos)):
        autopilot.gcs.mav.set_position_target_global_int_send(0, 1, 1, 6, 2552, lat, HOME_LON, 3.0, 0, 0, 0, 0, 0, 0, 0, 0)
        pos = autopilot.gcs.recv_match(type="LOCAL_POSITION_NED", blocking=True, timeout=0.05) or pos
    assert pos is not None and arrived(pos), pos


def test_highres_imu_and_ground_effect_switch(autopilot):
    autopilot.heartbeat()
    assert autopilot.command(511, 105, 100000).result == ACCEPTED
    imu = autopilot.wait(lambda m: True, "HIGHRES_IMU", 2)
    assert imu is not None and abs(imu.zacc + 9.81) < 0.05 and abs(imu.abs_pressure - 955.0) < 5.0, imu
    for value in (0, 1):
        autopilot.gcs.mav.param_set_send(1, 1, b"RP_GND_EFFECT", int32_bits(value), 6)
        echo = autopilot.wait(lambda m: m.param_id == "RP_GND_EFFECT", "PARAM_VALUE", 2)
        assert echo is not None and float_bits_to_int(echo.param_value) == value


def test_full_flight_takeoff_offboard_square_mission_rtl_land(autopilot):
    """The issue's end-to-end flight: arm → take-off → offboard square → 4-waypoint mission →
    RTL → land → auto-disarm, positions checked against the plan."""
    autopilot.heartbeat()
    plan = [(4, 0), (4, 4), (0, 4), (0, 0)]
    items = [(16, north(x), east(y), 3.0, 0.0) for x, y in plan] + [(20, 0, 0, 0.0, 0)]
    assert upload(autopilot, items) == 0
    autopilot.gcs.mav.param_set_send(1, 1, b"RTL_RETURN_ALT", 4.0, 9)
    assert autopilot.wait(lambda m: m.param_id == "RTL_RETURN_ALT", "PARAM_VALUE", 2) is not None
    autopilot.take_off()

    stream_position(autopilot, 0, 0, -2.5, 0.3)
    assert autopilot.command(176, 1, 6, 0).result == ACCEPTED
    for x, y in [(2, 0), (2, 2), (0, 2), (0, 0)]:
        pos = stream_position(autopilot, x, y, -2.5, 3.0)
        assert math.hypot(pos.x - x, pos.y - y) < 0.1 and abs(pos.z + 2.5) < 0.1, (x, y, pos)

    assert autopilot.command(176, 1, 4, 4).result == ACCEPTED
    reached, checked = follow_mission(autopilot, plan, 0, 5, 40)
    assert reached == [0, 1, 2, 3, 4] and len(checked) >= 3
    top = autopilot.wait(lambda m: m.relative_alt > 3900, "GLOBAL_POSITION_INT", 10)
    assert top is not None, "RTL climbs to RTL_RETURN_ALT"
    assert autopilot.wait(lambda m: "Disarmed" in m.text, "STATUSTEXT", 30) is not None
    pos = autopilot.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
    assert math.hypot(pos.x, pos.y) < 0.2 and abs(pos.z) < 0.2, "landed at home"
    assert autopilot.wait(lambda m: not m.base_mode & 128, "HEARTBEAT", 2) is not None


def test_battery_failsafe_announces_and_changes_mode(autopilot):
    """A small pack: BATTERY_STATUS drains, the failsafes announce themselves (critical
    STATUSTEXT) and the heartbeat shows AUTO.RTL, then AUTO.LAND."""
    autopilot.heartbeat()
    for name, value in [(b"BAT1_CAPACITY", 300.0), (b"COM_LOW_BAT_ACT", int32_bits(3))]:
        autopilot.gcs.mav.param_set_send(1, 1, name, value, 9 if name == b"BAT1_CAPACITY" else 6)
        assert autopilot.wait(lambda m, n=name.decode(): m.param_id == n, "PARAM_VALUE", 2) is not None
    full = autopilot.wait(lambda m: True, "BATTERY_STATUS", 3)
    assert full.battery_remaining == 100 and full.voltages[:3] == [4200] * 3 and full.voltages[3] == 65535
    assert autopilot.command(22).result == ACCEPTED
    assert autopilot.command(400, 1.0).result == ACCEPTED
    texts, modes = [], []
    deadline = time.monotonic() + 25
    while time.monotonic() < deadline and len(texts) < 3:
        m = autopilot.gcs.recv_match(type=["STATUSTEXT", "HEARTBEAT"], blocking=True, timeout=0.5)
        if m is None:
            continue
        if m.get_type() == "STATUSTEXT" and "battery" in m.text.lower():
            texts.append((m.severity, m.text))
        elif m.get_type() == "HEARTBEAT" and m.get_srcComponent() == 1 and m.custom_mode not in modes:
            modes.append(m.custom_mode)
    assert [t for _, t in texts] == ["Low battery: 15% remaining", "Critical battery (7%): returning",
                                     "Emergency battery (5%): landing"], texts
    assert all(severity == 2 for severity, _ in texts), "MAV_SEVERITY_CRITICAL"
    assert autopilot.wait(lambda m: m.custom_mode == (4 << 16) | (6 << 24), "HEARTBEAT", 3) is not None
    assert (4 << 16) | (5 << 24) in modes, "AUTO.RTL shown before AUTO.LAND"
    low = autopilot.wait(lambda m: True, "BATTERY_STATUS", 3)
    assert low.battery_remaining <= 5 and low.current_consumed > 280 and low.voltages[0] < 3550


def test_motor_failure_injection_lands_the_octocopter(rotorpilot_bin):
    """MAV_CMD_INJECT_FAILURE (motor 3 off) needs SYS_FAILURE_EN; the octocopter announces the
    failure, shows AUTO.LAND in its heartbeat, lands and disarms."""
    ap = Autopilot("--airframe", "octo")
    try:
        ap.heartbeat()
        assert ap.command(420, 101, 1, 3).result == DENIED, "SYS_FAILURE_EN = 0"
        ap.gcs.mav.param_set_send(1, 1, b"SYS_FAILURE_EN", int32_bits(1), 6)
        assert ap.wait(lambda m: m.param_id == "SYS_FAILURE_EN", "PARAM_VALUE", 2) is not None
        ap.take_off()
        assert ap.command(420, 101, 1, 3).result == ACCEPTED
        text = ap.wait(lambda m: m.text.startswith("Motor 3 failed"), "STATUSTEXT", 3)
        assert text is not None and text.text == "Motor 3 failed: landing" and text.severity == 2
        assert ap.wait(lambda m: m.custom_mode == (4 << 16) | (6 << 24), "HEARTBEAT", 3) is not None
        assert ap.wait(lambda m: "Disarmed" in m.text, "STATUSTEXT", 20) is not None
        actuators = ap.wait(lambda m: True, "ACTUATOR_OUTPUT_STATUS", 3)
        assert actuators.actuator[2] == 0.0
        pos = ap.wait(lambda m: True, "LOCAL_POSITION_NED", 2)
        assert math.hypot(pos.x, pos.y) < 0.5, "landed where it was"
    finally:
        ap.close()
