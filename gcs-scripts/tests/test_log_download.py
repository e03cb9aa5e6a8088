"""Flight logs of `rotorpilot run --log DIR` downloaded by the ground stations, unchanged or as they
download them, and compared byte for byte with the files on disk. Two logs are placed in
`DIR/log/` (PX4's layout) before the vehicle starts: `2026-01-01/10_00_00.ulg` (20 001 random
bytes, not a multiple of LOG_DATA's 90) and `2026-01-02/11_30_00.ulg` (3 bytes).

- QGroundControl's LogDownloadController, replayed with pymavlink: LOG_REQUEST_LIST (0 … 0xFFFF,
  missing entries re-requested after 0.5 s), then each log in chunks of 512 bins of 90 bytes
  (the last chunk rounded up to whole bins), a lost range re-requested from its offset after
  0.5 s of silence (some pieces are dropped on purpose); then the same log by MAVLink FTP as
  QGC's FTP manager reads it (burst, ReadFile for gaps) at PX4's path; then LOG_ERASE, after
  which the list is empty and the files are gone.
- MAVProxy 1.8.75, unchanged, typed at its prompt: `log list`, `log download all` (both logs, a
  LOG_REQUEST_END after each) and `ftp list` of a date directory. (Its `ftp get` routes replies
  by the random session number it sends, which PX4 does not echo: PX4 opens every file as
  session 0, so `ftp get` times out against PX4 and against this vehicle alike.)
- pymavlink's MAVFTP client (`pymavlink.mavftp`, its `ftp get` with a callback): one log.
- MAVSDK-Python's `logfile_download.py` example, unchanged, through `run_mavsdk_examples.py`
  (needs `unshare -n`, root: the example's ports are fixed).
- A flight of `rotorpilot run` without `--log` (its per-user state directory is the fixture's
  run directory's `state/`): the ULog of the flight appears in the default place the ready line
  names, announced "[logger] ./log/…", without a tlog; QGC's log list and download, MAVProxy's
  `log list` / `log download`, and MAVSDK-Python's log_files plugin (the calls of
  `logfile_download.py`) find it and bring it back byte for byte.

The vehicle binds port 0 (ports from its ready line), so the tests run side by side."""
import asyncio
import json
import os
import pathlib
import queue
import random
import re
import subprocess
import sys
import threading
import time

import pytest
from netns import can_unshare
from pymavlink.mavftp import MAVFTP, MAVFTPSettings
from qgc_replay import ACK, BIN, Qgc, qgc_download, qgc_list

from rotorpilot_gcs import connection_with_dialect, free_port
from rotorpilot_gcs.link import recent_text

# The logs placed before start: name under DIR/log → size [bytes], and their UTC times.
LOGS = {"2026-01-01/10_00_00.ulg": 20001, "2026-01-02/11_30_00.ulg": 3}
TIMES = [1767261600, 1767353400]
LIST_DIR = 3  # MAVLink FTP ListDirectory
RUNNER = pathlib.Path(__file__).resolve().parents[1] / "run_mavsdk_examples.py"
MAVPROXY = pathlib.Path(sys.executable).parent / "mavproxy.py"


def place_logs(log_dir):
    """The two logs written into `log_dir`/log (seeded random bytes); their bytes in id order."""
    placed = []
    for name, size in LOGS.items():
        path = log_dir / "log" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        placed.append(random.Random(name).randbytes(size))
        path.write_bytes(placed[-1])
    return placed


def test_qgc_lists_downloads_reads_by_ftp_and_erases_the_logs(autopilot_factory, tmp_path):
    placed = place_logs(tmp_path)
    qgc = Qgc(autopilot_factory(log=tmp_path))
    try:
        assert qgc.recv("HEARTBEAT", 5) is not None, "no HEARTBEAT"
        entries = qgc_list(qgc)
        assert sorted(entries) == [0, 1]
        listed = [(e.id, e.num_logs, e.last_log_num, e.size, e.time_utc) for e in entries.values()]
        assert sorted(listed) == [(0, 2, 1, 20001, TIMES[0]), (1, 2, 1, 3, TIMES[1])], listed
        # Pieces 40 … 49 and the last one of log 0 are lost once: QGC asks for the gap again.
        drop = {k * BIN for k in list(range(40, 50)) + [222]}
        for log_id, data in enumerate(placed):
            assert qgc_download(qgc, log_id, len(data), drop) == data, f"log {log_id}"

        # The same files at PX4's FTP path.
        days = qgc.ftp(LIST_DIR, data=b"/fs/microsd/log\0")
        assert days["opcode"] == ACK and days["data"].split(b"\0")[:2] == [b"D2026-01-01", b"D2026-01-02"], days
        files = qgc.ftp(LIST_DIR, data=b"/fs/microsd/log/2026-01-01\0")
        assert files["data"].split(b"\0")[0] == b"F10_00_00.ulg\t20001", files
        assert qgc.download("/fs/microsd/log/2026-01-01/10_00_00.ulg") == placed[0]
        assert qgc.download("/fs/microsd/log/2026-01-02/11_30_00.ulg") == placed[1]

        # LOG_ERASE (QGC's "Erase All"), then QGC's refresh: the list is empty.
        qgc.mav.mav.log_erase_send(1, 1)
        assert qgc_list(qgc) == {}
        assert not list((tmp_path / "log").rglob("*.ulg")), "the files are gone"
    finally:
        qgc.close()


class Typist:
    """MAVProxy at its prompt: lines typed on stdin, its output read line by line."""

    def __init__(self, argv, cwd):
        self.proc = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True,
                                     env=dict(os.environ, PYTHONUNBUFFERED="1"))
        self.lines, self.seen = queue.Queue(), []
        threading.Thread(target=lambda: [self.lines.put(x) for x in self.proc.stdout], daemon=True).start()

    def wait_for(self, pattern, timeout=30.0):
        """The first line from now on matching `pattern`; fails after `timeout` [s] without it."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                break
            self.seen.append(line)
            found = re.search(pattern, line)
            if found:
                return found
        pytest.fail(f"no {pattern!r} in MAVProxy's output:\n{''.join(self.seen[-60:])}")

    def type(self, line):
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait(timeout=10)


def test_mavproxy_lists_downloads_and_ftp_gets_the_logs_unchanged(autopilot_factory, tmp_path):
    placed = place_logs(tmp_path / "vehicle")
    ap = autopilot_factory(log=tmp_path / "vehicle")
    mavproxy = None
    try:
        mavproxy = Typist([sys.executable, str(MAVPROXY), f"--master={ap.gcs}",
                           "--default-modules=link,log,ftp", f"--state-basedir={tmp_path}"], tmp_path)
        mavproxy.wait_for(r"Detected vehicle 1:1")
        mavproxy.type("log list")
        mavproxy.wait_for(r"Log 1\s+numLogs 2 lastLog 1 size 3 ")
        # Both logs, the newest first, each ended with LOG_REQUEST_END before the next.
        mavproxy.type("log download all")
        mavproxy.wait_for(r"Finished downloading log1\.bin \(3 bytes")
        mavproxy.wait_for(r"Finished downloading log0\.bin \(20001 bytes")
        assert (tmp_path / "log0.bin").read_bytes() == placed[0]
        assert (tmp_path / "log1.bin").read_bytes() == placed[1]
        # Its FTP listing (after its ListDirectoryWithTime probe gets UnknownCommand, as from PX4).
        mavproxy.type("ftp list /fs/microsd/log/2026-01-01")
        mavproxy.wait_for(r"10_00_00\.ulg\s+20001")
    finally:
        if mavproxy is not None:
            mavproxy.close()


def test_pymavlink_mavftp_gets_a_log(autopilot_factory, tmp_path):
    placed = place_logs(tmp_path)
    ap = autopilot_factory(log=tmp_path)
    try:
        master = connection_with_dialect(ap.gcs, "common", source_system=254, source_component=190)
        # pymavlink's defaults but a shorter wait for silence after each operation (3.7 s).
        settings = MAVFTPSettings([("debug", int, 0), ("pkt_loss_tx", int, 0), ("pkt_loss_rx", int, 0),
                                   ("max_backlog", int, 5), ("burst_read_size", int, 80),
                                   ("write_size", int, 80), ("write_qsize", int, 5),
                                   ("idle_detection_time", float, 1.5), ("read_retry_time", float, 1.0),
                                   ("retry_time", float, 0.5)])
        ftp = MAVFTP(master, 1, 1, settings=settings)
        got, local = [], tmp_path / "mavftp.ulg"
        ftp.cmd_get(["/fs/microsd/log/2026-01-01/10_00_00.ulg", str(local)], callback=lambda fh: got.append(fh.read()))
        ftp.process_ftp_reply("OpenFileRO", timeout=30)
        assert got == [placed[0]] and local.read_bytes() == placed[0]
    finally:
        master.close()


@pytest.mark.skipif(not can_unshare(), reason="needs unshare -n (root)")
def test_mavsdk_logfile_download_example_brings_both_logs_back(rotorpilot_bin):
    env = dict(os.environ, ROTORPILOT_BIN=str(rotorpilot_bin))
    run = subprocess.run([sys.executable, str(RUNNER), "logfile_download", "--timeout", "90"],
                         capture_output=True, text=True, env=env, timeout=200, check=False)
    assert run.stdout.strip(), run.stderr[-2000:]
    verdict = json.loads(run.stdout.strip().splitlines()[-1])
    # The runner compares log-<date>.ulog with the placed logs byte for byte.
    assert verdict["verdict"] == "works" and verdict["exit"] == "0", verdict


def flight_without_log(autopilot_factory):
    """A take-off and landing of `rotorpilot run` without `--log`; (the vehicle, its flight log)."""
    ap = autopilot_factory(log=None, speedup=4)
    place = ap.workdir / "state" / "rotorpilot" / "instance-0"
    assert ap.ready["log_dir"] == str(place) == ap.vehicles[0]["log_dir"]
    assert ap.log_dir == place and not place.exists(), "nothing before a log begins"
    ap.vehicle.wait_armable()
    since = time.monotonic()
    ap.vehicle.takeoff()
    ap.vehicle.land()
    ap.vehicle.wait_disarmed(timeout=60)
    (path,) = ap.flight_logs()
    name = path.relative_to(place).as_posix()
    assert recent_text(ap.vehicle.conn, since, "[logger]") == f"[logger] ./{name}"
    assert not (place / "flight.tlog").exists(), "the tlog only with --log"
    time.sleep(0.5)  # closed and flushed by the writer after the disarming
    return ap, path


@pytest.mark.filterwarnings("ignore:The 'mavsdk' package has been renamed:FutureWarning",
                            "ignore:path is deprecated:DeprecationWarning")
def test_a_flight_without_log_is_found_and_downloaded_by_qgc_mavproxy_and_mavsdk(autopilot_factory, tmp_path):
    ap, path = flight_without_log(autopilot_factory)
    flown = path.read_bytes()
    assert flown.startswith(b"ULog")
    qgc = Qgc(ap)
    try:
        entries = qgc_list(qgc)
        assert [(e.id, e.num_logs, e.size) for e in entries.values()] == [(0, 1, len(flown))]
        assert qgc_download(qgc, 0, len(flown), set()) == flown
    finally:
        qgc.close()

    mavproxy = Typist([sys.executable, str(MAVPROXY), f"--master={ap.gcs}", "--default-modules=link,log",
                       f"--state-basedir={tmp_path}"], tmp_path)
    try:
        mavproxy.wait_for(r"Detected vehicle 1:1")
        mavproxy.type("log list")
        mavproxy.wait_for(rf"Log 0\s+numLogs 1 lastLog 0 size {len(flown)} ")
        mavproxy.type("log download 0 flight.ulg")
        mavproxy.wait_for(rf"Finished downloading flight\.ulg \({len(flown)} bytes")
        assert (tmp_path / "flight.ulg").read_bytes() == flown
    finally:
        mavproxy.close()

    async def mavsdk_download():
        from mavsdk import System

        drone = System(port=free_port())
        await drone.connect(system_address=ap.api)
        try:
            async for state in drone.core.connection_state():
                if state.is_connected:
                    break
            entries = await drone.log_files.get_entries()
            local = tmp_path / "mavsdk.ulg"
            async for progress in drone.log_files.download_log_file(entries[0], str(local)):
                if progress.progress >= 1.0:
                    break
            return [e.size_bytes for e in entries], local.read_bytes()
        finally:
            drone._stop_mavsdk_server()  # the mavsdk_server System.connect started

    sizes, got = asyncio.run(asyncio.wait_for(mavsdk_download(), 90))
    assert sizes == [len(flown)] and got == flown


@pytest.mark.parametrize("mode, logs", [(-1, 0), (1, 1)])
def test_sdlog_mode_chooses_what_a_flight_leaves(autopilot_factory, mode, logs):
    # -1: nothing written; 1 (PX4 SITL's): one log from start through the flight to its disarming.
    ap = autopilot_factory(log=None, speedup=4, params={"SDLOG_MODE": mode})
    ap.vehicle.wait_armable()
    ap.vehicle.arm()
    ap.vehicle.disarm()
    time.sleep(0.5)
    assert len(ap.flight_logs()) == logs
    assert (ap.log_dir / "log").exists() == (logs > 0)
