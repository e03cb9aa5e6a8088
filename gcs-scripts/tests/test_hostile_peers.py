"""Peers a client can multiply: 5 000 source ports each write to the GCS link once per round (a
GCS HEARTBEAT, a shell line, a parameter-list request and an FTP directory with a 200-byte name),
three rounds. The vehicle's memory stays bounded (RSS under 64 MB, no growth from round to
round), the telemetry it sends stays bounded (at most MAX_PEERS = 8 learned peers get the
streams the configured ground station gets, whatever the number of addresses), FTP answers a
full scratch area with FailErrno ENOSPC, and the ground station keeps being served."""
import resource
import selectors
import socket
import time

from pymavlink.dialects.v20 import common as mavlink2

MAX_PEERS = 8
ADDRESSES = 5_000
RSS_BOUND_KB = 64 * 1024
FTP_FAIL_ERRNO, FTP_NAK, ENOSPC = 2, 129, 28


def rss_kb(pid):
    """Resident memory of process `pid` [kB]."""
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise AssertionError("no VmRSS")


def frames(k):
    """What address number `k` sends: heartbeat, shell line, parameter list, FTP mkdir."""
    mav = mavlink2.MAVLink(None, srcSystem=255, srcComponent=190)
    mav.robust_parsing = True
    heartbeat = mavlink2.MAVLink_heartbeat_message(mavlink2.MAV_TYPE_GCS, mavlink2.MAV_AUTOPILOT_INVALID, 0, 0, 4, 3)
    shell = mavlink2.MAVLink_serial_control_message(10, 2 | 4, 0, 0, 4, list(b"ver\n") + [0] * 66)
    plist = mavlink2.MAVLink_param_request_list_message(1, 1)
    path = f"/fs/microsd/{k:05d}" + "x" * 200
    payload = bytearray(251)
    payload[0:2] = (2 * k % 65536).to_bytes(2, "little")
    payload[3], payload[4] = 9, len(path)  # CreateDirectory, size
    payload[12:12 + len(path)] = path.encode()
    ftp = mavlink2.MAVLink_file_transfer_protocol_message(0, 1, 1, list(payload))
    return [m.pack(mav) for m in (heartbeat, shell, plist, ftp)]


def read_one(sock, parser_for, seen):
    """Reads one datagram from `sock` (False when none is queued): the vehicle times of its
    ATTITUDE messages [ms] and its FTP NAK codes go into `seen`."""
    try:
        data = sock.recv(65536)
    except BlockingIOError:
        return False
    for m in parser_for(sock).parse_buffer(data) or []:
        kind = m.get_type()
        if kind == "ATTITUDE":
            seen["attitude_ms"].append(m.time_boot_ms)
        elif kind == "FILE_TRANSFER_PROTOCOL" and m.payload[3] == FTP_NAK:
            seen["ftp_naks"].add((m.payload[12], m.payload[13]))
    return True


def in_window(seen, window_ms):
    """How many of `seen`'s ATTITUDE messages the vehicle stamped inside `window_ms`."""
    lo, hi = window_ms
    return sum(lo <= t < hi for t in seen["attitude_ms"])


def test_five_thousand_source_ports_leave_memory_and_telemetry_bounded(autopilot):
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, max(soft, ADDRESSES + 500)), hard))
    host, port = autopilot.gcs_bind.rsplit(":", 1)
    target = (host, int(port))
    remote = autopilot.vehicle.conn.port  # the configured ground station's socket
    autopilot.vehicle.sleep(3.0)
    before = rss_kb(autopilot.proc.pid)
    rounds = []
    for _ in range(3):
        sel = selectors.DefaultSelector()
        socks, parsers = [], {}
        for k in range(ADDRESSES):
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.bind(("127.0.0.1", 0))
            s.setblocking(False)
            for frame in frames(k):
                s.sendto(frame, target)
            socks.append(s)
            sel.register(s, selectors.EVENT_READ)
        sel.register(remote, selectors.EVENT_READ)

        def parser_for(sock):
            return parsers.setdefault(sock, mavlink2.MAVLink(None))

        flood = {"attitude_ms": [], "ftp_naks": set()}
        alone = {"attitude_ms": [], "ftp_naks": set()}
        end = time.monotonic() + 4.0
        while time.monotonic() < end:
            for key, _ in sel.select(0.05):
                read_one(key.fileobj, parser_for, alone if key.fileobj is remote else flood)
        # Both counts over the same two seconds of vehicle time, ending half a second before the
        # last ATTITUDE the ground station read (however late a loaded machine reads it): by
        # then every address has written, so the peer table holds still.
        last = max(alone["attitude_ms"], default=0)
        window_ms = (last - 2500, last - 500)
        rounds.append((in_window(flood, window_ms), in_window(alone, window_ms), flood["ftp_naks"],
                       rss_kb(autopilot.proc.pid)))
        sel.unregister(remote)
        for s in socks:
            s.close()
        sel.close()
    for flood_n, alone_n, _, rss in rounds:
        # ATTITUDE at 15 Hz on PX4's GCS link: 30 in the window.
        assert alone_n >= 25, alone_n
        # Telemetry to the flooders: at most MAX_PEERS times what one ground station gets.
        assert flood_n <= MAX_PEERS * alone_n * 1.1, (flood_n, alone_n)
        assert rss < RSS_BOUND_KB, f"RSS {rss} kB"
    assert (FTP_FAIL_ERRNO, ENOSPC) in rounds[-1][2], "a full scratch area is ENOSPC"
    growth = rounds[-1][3] - rounds[0][3]
    assert growth < 4 * 1024, f"RSS grew by {growth} kB from the first round to the last (from {before} kB)"
    # The ground station is still served, and answered.
    assert autopilot.vehicle.param_get("MPC_XY_VEL_MAX") == 12.0
