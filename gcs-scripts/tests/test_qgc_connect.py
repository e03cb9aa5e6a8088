"""QGroundControl's connect sequence, replayed end to end against the binary with pymavlink (dialect
`common`). The generated dialects of the pinned pymavlink 2.4.49, `common` included, lack
PROTOCOL_VERSION 300, COMPONENT_METADATA 397, AVAILABLE_MODES 435 and CURRENT_MODE 436: they
arrive as UNKNOWN_<id> with their raw payload, decoded here from common.xml's wire layout.

In the order of QGC's InitialConnectStateMachine, each command tried 3 times with 3 s for its ACK
as QGC's command queue does: REQUEST_MESSAGE AUTOPILOT_VERSION (148), PROTOCOL_VERSION (300),
AVAILABLE_MODES (435, index 1 then each next index until `number_modes`, as QGC's StandardModes
asks), COMPONENT_METADATA (397), then the general metadata JSON and the parameter JSON it names
downloaded over MAVLink FTP as QGC's FTPManager does (OpenFileRO, BurstReadFile, ReadFile for the
gaps, TerminateSession), both `.xz` files as PX4 serves them and inflated with Python's `lzma` as
QGC inflates them (COMPONENT_METADATA.file_crc checked against the inflated general JSON, as PX4's
`generate_crc.py` computes it, and `fileCrc` against the downloaded parameter `.xz`);
PARAM_REQUEST_LIST (every PARAM_VALUE, `_HASH_CHECK` first); MISSION_REQUEST_LIST for the mission,
the fence and the rally points (empty, then a `.plan`'s fence and rally points uploaded and
downloaded back identical); and a MAVLink shell round trip over SERIAL_CONTROL (`ver all`)
as QGC's MAVLink console sends it. Ports are ephemeral (port 0, read from the ready line)."""
import json
import lzma
import pathlib
import time

import pytest
from qgc_replay import ACCEPTED, ACK_TIMEOUT_S, DENIED, DEV_SHELL, REPLY, SHELL_FLAGS, Qgc, crc32_part

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavutil
from rotorpilot_gcs.missions import FENCE, RALLY

PLAN = pathlib.Path(__file__).resolve().parent / "data" / "fence_rally.plan"


@pytest.fixture
def qgc(autopilot):
    link = Qgc(autopilot)
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

    # COMPONENT_METADATA, then both metadata files over MAVLink FTP, `.xz` as PX4 serves them,
    # CRCs checked.
    result, got = qgc.request_message(397)
    assert result == ACCEPTED
    meta = got["COMPONENT_METADATA"][0]
    assert meta.uri == "mftp://etc/extras/component_general.json.xz", meta.uri
    general_bytes = lzma.decompress(qgc.download(meta.uri[len("mftp:/"):]), format=lzma.FORMAT_XZ)
    assert crc32_part(general_bytes) == meta.file_crc
    general = json.loads(general_bytes)
    assert general["version"] == 1
    [param_type] = [t for t in general["metadataTypes"] if t["type"] == 1]
    assert param_type["uri"] == "mftp://etc/extras/parameters.json.xz", param_type
    param_xz = qgc.download(param_type["uri"][len("mftp:/"):])
    assert crc32_part(param_xz) == param_type["fileCrc"]
    param_bytes = lzma.decompress(param_xz, format=lzma.FORMAT_XZ)
    assert len(param_xz) * 4 < len(param_bytes), (len(param_xz), len(param_bytes))
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
    plan = gcs.plans.load_qgc_plan(PLAN)
    qgc.mav.target_system, qgc.mav.target_component = 1, 1
    for mission_type, items in ((FENCE, plan.fence), (RALLY, plan.rally)):
        gcs.missions.upload_mission(qgc.mav, items, mission_type)
        assert gcs.missions.download_mission(qgc.mav, mission_type) == items, mission_type

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
