"""QGroundControl's connect sequence, replayed end to end against the binary with pymavlink (dialect
`common`). The generated dialects of the pinned pymavlink 2.4.49, `common` included, lack
PROTOCOL_VERSION 300, COMPONENT_METADATA 397, AVAILABLE_MODES 435 and CURRENT_MODE 436: they
arrive as UNKNOWN_<id> with their raw payload, decoded here from common.xml's wire layout.

In the order of QGC's InitialConnectStateMachine, each command tried 3 times with 3 s for its ACK
as QGC's command queue does: REQUEST_MESSAGE AUTOPILOT_VERSION (148), PROTOCOL_VERSION (300),
AVAILABLE_MODES (435, index 1 then each next index until `number_modes`, as QGC's StandardModes
asks), COMPONENT_METADATA (397), then the general metadata JSON and the parameter JSON it names
downloaded over MAVLink FTP as QGC's FTPManager does (OpenFileRO, BurstReadFile, ReadFile for the
gaps, TerminateSession; the CRC checked against COMPONENT_METADATA.file_crc and `fileCrc`);
PARAM_REQUEST_LIST (every PARAM_VALUE, `_HASH_CHECK` first); MISSION_REQUEST_LIST for the mission,
the fence and the rally points (empty, then a `.plan`'s fence and rally points uploaded and
downloaded back identical); and a MAVLink shell round trip over SERIAL_CONTROL (`ver all`)
as QGC's MAVLink console sends it. Ports are ephemeral (port 0, read from the ready line)."""
import json
import os
import struct
import subprocess
import time
from types import SimpleNamespace

import pytest

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402
from test_fence_rally import FENCE, RALLY, download, fence_items, qgc_plan, rally_items, upload  # noqa: E402

QGC = (255, 190)  # QGroundControl's system and component ids
TRIES, ACK_TIMEOUT_S = 3, 3.0
ACCEPTED, DENIED = 0, 2
# MAVLink FTP opcodes and the reply opcodes.
TERMINATE, OPEN_RO, READ, BURST = 1, 4, 5, 15
ACK, NAK = 128, 129
FTP_DATA_MAX = 239
# SERIAL_CONTROL: the shell device; QGC's flags EXCLUSIVE | RESPOND | MULTI; the REPLY flag.
DEV_SHELL, SHELL_FLAGS, REPLY = 10, 4 | 2 | 16, 1


# Wire layouts (fields sorted by size, as MAVLink 2 sends them) of the messages pymavlink lacks.
RAW_LAYOUTS = {
    300: ("PROTOCOL_VERSION", "<HHH8s8s", ("version", "min_version", "max_version", "spec_version_hash",
                                           "library_version_hash")),
    397: ("COMPONENT_METADATA", "<II100s", ("time_boot_ms", "file_crc", "uri")),
    435: ("AVAILABLE_MODES", "<IIBBB35s", ("custom_mode", "properties", "number_modes", "mode_index",
                                           "standard_mode", "mode_name")),
}


class PlanLink:
    """The plan helpers' view of the QGC link (`gcs`, `wait`, `pending`)."""

    def __init__(self, qgc):
        self.gcs, self.qgc, self.pending = qgc.mav, qgc, []

    def wait(self, predicate, types, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.qgc.recv(types, max(0.0, deadline - time.monotonic()))
            if m is not None and predicate(m):
                return m
        return None


def decode_raw(m):
    """A message pymavlink left UNKNOWN_<id>, decoded when RAW_LAYOUTS knows it (else `m`)."""
    if not m.get_type().startswith("UNKNOWN_"):
        return m
    msg_id = int(m.get_type()[8:])
    if msg_id not in RAW_LAYOUTS:
        return m
    name, layout, fields = RAW_LAYOUTS[msg_id]
    frame = bytes(m.data)  # the whole MAVLink 2 frame: 10 header bytes, then the payload
    assert frame[0] == 0xFD, frame
    payload = frame[10:10 + frame[1]] + bytes(struct.calcsize(layout))  # trailing zeros are trimmed
    values = struct.unpack_from(layout, payload)
    decoded = SimpleNamespace(**{k: v.split(b"\0")[0].decode() if k in ("uri", "mode_name") else v
                                 for k, v in zip(fields, values)})
    decoded.get_type = lambda: name
    decoded.get_msgId = lambda: msg_id
    decoded.get_srcSystem = lambda: frame[5]
    decoded.get_srcComponent = lambda: frame[6]
    return decoded


def crc32_part(data, state=0):
    """PX4's crc32part: the reflected 0xEDB88320 CRC without the initial and final inversion."""
    for byte in data:
        state ^= byte
        for _ in range(8):
            state = (state >> 1) ^ 0xEDB88320 if state & 1 else state >> 1
    return state


class Qgc:
    """A pymavlink link to `rotorpilot run` with QGroundControl's ids, heartbeating as QGC does."""

    def __init__(self, binary, *args):
        """`rotorpilot run` on ephemeral ports with `args` added (`--log DIR`, …)."""
        self.proc = subprocess.Popen(
            [str(binary), "run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0", "--api",
             "127.0.0.1:9", "--duration", "120", *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = json.loads(self.proc.stdout.readline())
        self.mav = mavutil.mavlink_connection(f"udpout:{self.ready['gcs_bind']}", dialect="common",
                                              source_system=QGC[0], source_component=QGC[1])
        self.last_heartbeat = 0.0
        self.ftp_seq = 0

    def close(self):
        self.proc.send_signal(2)
        self.proc.wait(timeout=10)

    def recv(self, types, timeout):
        """The next message of `types` within `timeout` [s] (heartbeating meanwhile), or None."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if time.monotonic() - self.last_heartbeat > 1.0:
                self.mav.mav.heartbeat_send(6, 8, 0, 0, 0)  # MAV_TYPE_GCS, MAV_AUTOPILOT_INVALID
                self.last_heartbeat = time.monotonic()
            m = self.mav.recv_match(blocking=True, timeout=0.2)
            if m is None:
                continue
            m = decode_raw(m)
            ours = m.get_srcSystem() == 1 and m.get_srcComponent() == 1
            wanted = types is None or m.get_type() in ([types] if isinstance(types, str) else types)
            if ours and wanted:
                return m
        return None

    def request_message(self, message_id, param2=0.0):
        """REQUEST_MESSAGE as QGC sends it (3 tries × 3 s): the ACK's result and the messages that
        came with it (by type)."""
        for attempt in range(TRIES):
            self.mav.mav.command_long_send(1, 1, 512, attempt, message_id, param2, 0, 0, 0, 0, 0)
            got, deadline = {}, time.monotonic() + ACK_TIMEOUT_S
            ack = None
            while time.monotonic() < deadline:
                m = self.recv(None, deadline - time.monotonic())
                if m is None:
                    break
                if m.get_type() == "COMMAND_ACK" and m.command == 512:
                    ack = m
                elif m.get_msgId() == message_id:
                    got.setdefault(m.get_type(), []).append(m)
                if ack is not None and (got or ack.result != ACCEPTED):
                    return ack.result, got
        pytest.fail(f"REQUEST_MESSAGE {message_id} ({param2}) unanswered after {TRIES} tries")

    def ftp(self, opcode, session=0, offset=0, data=b""):
        """One MAVLink FTP request; the reply payload fields (seq, session, opcode, size,
        req_opcode, burst_complete, offset, data)."""
        self.ftp_seq = (self.ftp_seq + 1) % 65536
        header = struct.pack("<HBBBBBBI", self.ftp_seq, session, opcode, len(data), 0, 0, 0, offset)
        payload = list(header + data) + [0] * (251 - 12 - len(data))
        for _ in range(TRIES):
            self.mav.mav.file_transfer_protocol_send(0, 1, 1, payload)
            reply = self.ftp_reply(ACK_TIMEOUT_S)
            if reply is not None and reply["seq"] == (self.ftp_seq + 1) % 65536:
                return reply
        pytest.fail(f"FTP opcode {opcode} unanswered")

    def ftp_reply(self, timeout):
        m = self.recv("FILE_TRANSFER_PROTOCOL", timeout)
        if m is None:
            return None
        raw = bytes(m.payload)
        seq, session, opcode, size, req, burst_complete, _, offset = struct.unpack("<HBBBBBBI", raw[:12])
        return {"seq": seq, "session": session, "opcode": opcode, "size": size, "req_opcode": req,
                "burst_complete": burst_complete, "offset": offset, "data": raw[12:12 + size]}

    def download(self, path):
        """A file as QGC's FTPManager downloads it: OpenFileRO (the size in the ACK), BurstReadFile
        from 0 until a burst-complete frame, ReadFile for each missing block, TerminateSession."""
        opened = self.ftp(OPEN_RO, data=path.encode() + b"\0")
        assert opened["opcode"] == ACK, (path, opened)
        session, size = opened["session"], struct.unpack("<I", opened["data"][:4])[0]
        blocks = {}
        burst = self.ftp(BURST, session=session, offset=0)
        while True:
            assert burst["opcode"] in (ACK, NAK), burst
            if burst["opcode"] == ACK:
                blocks[burst["offset"]] = burst["data"]
                if burst["burst_complete"] or burst["offset"] + len(burst["data"]) >= size:
                    break
            else:
                break  # EOF
            burst = self.ftp_reply(ACK_TIMEOUT_S)
            assert burst is not None, f"burst of {path} stalled"
        offset = 0
        data = bytearray()
        while offset < size:
            if offset not in blocks:
                read = self.ftp(READ, session=session, offset=offset)
                assert read["opcode"] == ACK, read
                blocks[offset] = read["data"]
            data += blocks[offset]
            offset += len(blocks[offset])
        closed = self.ftp(TERMINATE, session=session)
        assert closed["opcode"] == ACK, closed
        assert len(data) == size
        return bytes(data)


@pytest.fixture
def qgc(rotorpilot_bin):
    link = Qgc(rotorpilot_bin)
    assert link.recv("HEARTBEAT", 5) is not None, "no HEARTBEAT"
    yield link
    link.close()


def test_qgc_initial_connect_sequence(qgc):
    # AUTOPILOT_VERSION: MAVLink 2, FTP, mission int and the PX4 flight stack's capabilities.
    result, got = qgc.request_message(148)
    assert result == ACCEPTED
    version = got["AUTOPILOT_VERSION"][0]
    caps = mavutil.mavlink.enums["MAV_PROTOCOL_CAPABILITY"]
    for name in ("MAV_PROTOCOL_CAPABILITY_MAVLINK2", "MAV_PROTOCOL_CAPABILITY_FTP",
                 "MAV_PROTOCOL_CAPABILITY_MISSION_INT", "MAV_PROTOCOL_CAPABILITY_COMMAND_INT"):
        bit = next(k for k, v in caps.items() if v.name == name)
        assert version.capabilities & bit, name

    result, got = qgc.request_message(300)
    assert result == ACCEPTED
    protocol = got["PROTOCOL_VERSION"][0]
    assert (protocol.version, protocol.min_version, protocol.max_version) == (200, 100, 200)

    # AVAILABLE_MODES one index at a time, as QGC's StandardModes asks.
    modes, index = [], 1
    while True:
        result, got = qgc.request_message(435, index)
        assert result == ACCEPTED, index
        mode = got["AVAILABLE_MODES"][0]
        assert mode.mode_index == index
        modes.append(mode)
        if index == mode.number_modes:
            break
        index += 1
    names = {m.custom_mode: m.mode_name for m in modes}
    standard = {m.custom_mode: m.standard_mode for m in modes}
    # POSCTL, POSCTL.ORBIT and ALTCTL are the standard position hold (1), orbit (2) and altitude
    # hold (4), named by the standard.
    assert (standard[196608], names[196608], standard[16973824], standard[131072]) == (1, "", 2, 4), modes
    assert names[50593792] == "Hold" and len(modes) == modes[0].number_modes >= 10, names
    assert qgc.request_message(435, len(modes) + 1)[0] == DENIED

    # COMPONENT_METADATA, then both metadata files over MAVLink FTP, CRCs checked.
    result, got = qgc.request_message(397)
    assert result == ACCEPTED
    meta = got["COMPONENT_METADATA"][0]
    assert meta.uri.startswith("mftp://"), meta.uri
    general_bytes = qgc.download(meta.uri[len("mftp:/"):])
    assert crc32_part(general_bytes) == meta.file_crc
    general = json.loads(general_bytes)
    assert general["version"] == 1
    [param_type] = [t for t in general["metadataTypes"] if t["type"] == 1]
    param_bytes = qgc.download(param_type["uri"][len("mftp:/"):])
    assert crc32_part(param_bytes) == param_type["fileCrc"]
    described = {p["name"]: p for p in json.loads(param_bytes)["parameters"]}
    assert described["MPC_XY_VEL_MAX"]["type"] == "Float" and described["MPC_XY_VEL_MAX"]["units"]

    # Every parameter, _HASH_CHECK first, each index once; every one described in the metadata.
    qgc.mav.mav.param_request_list_send(1, 1)
    values = []
    while True:
        m = qgc.recv("PARAM_VALUE", 3.0)
        if m is None:
            break
        values.append(m)
        if len({v.param_index for v in values if v.param_id != "_HASH_CHECK"}) == m.param_count:
            break
    assert values and values[0].param_id == "_HASH_CHECK", values[:1]
    listed = {v.param_id: v for v in values[1:]}
    assert len(listed) == values[1].param_count, (len(listed), values[1].param_count)
    assert set(listed) == set(described), set(listed) ^ set(described)

    # The plans: mission (0), fence (1), rally points (2).
    counts = {}
    for mission_type in (0, 1, 2):
        qgc.mav.mav.mission_request_list_send(1, 1, mission_type)
        answer = qgc.recv(["MISSION_COUNT", "MISSION_ACK"], ACK_TIMEOUT_S)
        assert answer is not None, f"mission type {mission_type} unanswered"
        counts[mission_type] = (answer.get_type(), answer.mission_type, getattr(answer, "count", None))
    # A fresh vehicle: an empty mission, each answer carrying the type asked for.
    assert counts[0] == ("MISSION_COUNT", 0, 0), counts
    assert counts[1] == ("MISSION_COUNT", 1, 0) and counts[2] == ("MISSION_COUNT", 2, 0), counts
    # A vehicle holding a fence and rally points (uploaded as QGC's plan managers send a `.plan`):
    # QGC's download of each plan brings back exactly what went up.
    link = PlanLink(qgc)
    plan = qgc_plan()
    for mission_type, items in ((FENCE, fence_items(plan)), (RALLY, rally_items(plan))):
        assert upload(link, mission_type, items).type == 0, mission_type
        assert download(link, mission_type) == items, mission_type

    # The MAVLink console: `ver all` over SERIAL_CONTROL, answered by the shell with REPLY frames.
    line = b"ver all\n"
    qgc.mav.mav.serial_control_send(DEV_SHELL, SHELL_FLAGS, 0, 0, len(line), list(line) + [0] * (70 - len(line)))
    text, deadline = b"", time.monotonic() + ACK_TIMEOUT_S
    while b"FW version" not in text or not text.rstrip().endswith(b">"):
        m = qgc.recv("SERIAL_CONTROL", max(0.0, deadline - time.monotonic()))
        assert m is not None, text
        assert m.device == DEV_SHELL and m.flags & REPLY
        text += bytes(m.data[: m.count])
    assert b"HW arch: ROTORPILOT_SITL" in text and b"FW git tag: v" in text, text
