"""QGroundControl's side of the protocols, replayed with pymavlink for the tests: its link
(QGC's ids, the `common` dialect, a heartbeat a second, the messages pymavlink 2.4.49's dialects
lack decoded from their raw payload), its command queue's REQUEST_MESSAGE (3 tries × 3 s), its
FTPManager's file download (OpenFileRO, BurstReadFile, ReadFile for the gaps, TerminateSession)
and its LogDownloadController's log list and download (LOG_REQUEST_LIST / LOG_REQUEST_DATA in
chunks of 512 bins of 90 bytes, lost ranges asked again after 0.5 s). Used by
test_qgc_connect.py, test_log_download.py and test_flight_logs.py."""
import struct
import time
from types import SimpleNamespace

import pytest

from rotorpilot_gcs import connection_with_dialect

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
    """A pymavlink link to `rotorpilot run` with QGroundControl's ids (dialect `common`),
    heartbeating as QGC does."""

    def __init__(self, autopilot):
        """A link to `autopilot`'s GCS port (the plugin's `Autopilot`)."""
        self.mav = connection_with_dialect(autopilot.gcs, "common", source_system=QGC[0],
                                           source_component=QGC[1])
        self.last_heartbeat = 0.0
        self.ftp_seq = 0

    def close(self):
        self.mav.close()

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


# QGC's LogDownloadController.
BIN = 90  # bytes of LOG_DATA
BINS = 512  # QGC's bins per chunk
QGC_TIMEOUT_S = 0.5  # QGC's kTimeOutMs


def qgc_list(qgc):
    """LOG_REQUEST_LIST as QGC sends it; the entries by id (missing ones re-requested)."""
    qgc.mav.mav.log_request_list_send(1, 1, 0, 0xFFFF)
    entries, num_logs, retries = {}, None, 0
    first = qgc.recv("LOG_ENTRY", 5.0)  # kRequestLogListTimeoutMs
    assert first is not None, "LOG_REQUEST_LIST unanswered"
    m = first
    while True:
        if m is not None:
            num_logs = m.num_logs
            if num_logs == 0:
                return {}
            entries[m.id] = m
        missing = [i for i in range(num_logs) if i not in entries]
        if not missing:
            return entries
        if m is None:
            retries += 1
            assert retries <= 3, f"entries {missing} never came"
            qgc.mav.mav.log_request_list_send(1, 1, missing[0], missing[-1])
        m = qgc.recv("LOG_ENTRY", QGC_TIMEOUT_S)


def qgc_download(qgc, log_id, size, drop):
    """Log `log_id` as QGC's LogDownloadController downloads it; the pieces at the offsets in
    `drop` are ignored the first time they arrive (lost on the way)."""
    chunk_size = BINS * BIN
    chunks = -(-size // chunk_size)
    chunk, data, dropped, retries = 0, bytearray(size), set(), 0

    def bins(c):
        return min(-(-(size - c * chunk_size) // BIN), BINS)

    def request_gap():
        start = table.index(False)
        end = table.index(True, start) if True in table[start:] else len(table)
        qgc.mav.mav.log_request_data_send(1, 1, log_id, chunk * chunk_size + start * BIN, (end - start) * BIN)

    table = [False] * bins(0)
    qgc.mav.mav.log_request_data_send(1, 1, log_id, 0, len(table) * BIN)
    while True:
        m = qgc.recv("LOG_DATA", QGC_TIMEOUT_S)
        if m is None:
            retries += 1
            assert retries < 10, f"log {log_id} stalled at chunk {chunk}: {table.count(False)} bins missing"
            request_gap()
            continue
        if m.id != log_id or m.ofs % BIN or m.ofs > size or m.ofs // chunk_size != chunk:
            continue  # QGC ignores another log's, misaligned and out-of-chunk pieces
        if m.ofs in drop and m.ofs not in dropped:
            dropped.add(m.ofs)
            continue
        retries = 0
        b = (m.ofs - chunk * chunk_size) // BIN
        table[b] = True
        data[m.ofs:m.ofs + m.count] = bytes(m.data[:m.count])
        if all(table):
            if chunk + 1 == chunks:
                assert dropped == set(drop) & set(range(0, size, BIN)), dropped
                return bytes(data)
            chunk += 1
            table = [False] * bins(chunk)
            qgc.mav.mav.log_request_data_send(1, 1, log_id, chunk * chunk_size, len(table) * BIN)
        elif b < len(table) - 1 and table[b + 1]:
            request_gap()  # the end of a gap being filled: the next gap
