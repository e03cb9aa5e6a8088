"""MAVLink 2 signing against `rotorpilot run --signing-key FILE` with pymavlink's `setup_signing`:
a signed ground station flies; unsigned and wrong-key senders get nothing and change nothing;
replayed and stale frames are rejected; SETUP_SIGNING over the link; the timestamp persists."""
import pathlib
import stat
import time

import pytest

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink, mavutil

ACCEPTED = mavlink.MAV_RESULT_ACCEPTED
NAN = float("nan")

KEY = bytes(range(1, 33))
WRONG_KEY = bytes(range(101, 133))
REQUEST_MESSAGE, AUTOPILOT_VERSION = 512, 148
SIGNING_EPOCH = 1420070400


def now_timestamp():
    """The signing clock now [10 µs since 2015]."""
    return int((time.time() - SIGNING_EPOCH) * 100_000)


def key_file(tmp_path, key=KEY):
    path = tmp_path / "signing.key"
    path.write_bytes(key)
    return path


def sender(ap, key=None, link_id=3):
    """A pymavlink connection sending to the vehicle's GCS port (it hears only what is sent back)."""
    conn = mavutil.mavlink_connection(ap.gcs, source_system=255, source_component=190)
    if key is not None:
        conn.setup_signing(key, sign_outgoing=True, link_id=link_id)
    return conn


def anything(conn, timeout):
    """The first message `conn` receives within `timeout` [s], or None."""
    return conn.recv_match(blocking=True, timeout=timeout)


def ack_for(conn, command, timeout=1.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        m = conn.recv_match(type="COMMAND_ACK", blocking=True, timeout=max(0.0, deadline - time.monotonic()))
        if m is not None and m.command == command:
            return m
    return None


def test_signed_gcs_flies_and_everything_it_receives_is_signed(autopilot_factory, tmp_path):
    path = key_file(tmp_path)
    ap = autopilot_factory(args=["--signing-key", path])
    ap.vehicle.conn.setup_signing(KEY, sign_outgoing=True, link_id=1)
    ap.vehicle.takeoff()
    ap.vehicle.land()
    ap.vehicle.wait("STATUSTEXT", lambda m: "Disarmed" in m.text, 15)  # landed and disarmed
    signing = ap.vehicle.conn.mav.signing
    assert signing.goodsig_count > 100
    assert (signing.badsig_count, signing.unsigned_count, signing.reject_count) == (0, 0, 0)
    assert ap.proc.poll() is None
    ap.stop()
    # Neither the key nor anything of it in what the process printed.
    out = ap.stdout_text() + ap.stderr_text()
    assert KEY.hex() not in out and "1, 2, 3, 4, 5, 6, 7, 8" not in out
    persisted = int((tmp_path / "signing.key.timestamp").read_text())
    assert persisted >= now_timestamp() - 60 * 100_000


def test_unsigned_and_wrong_key_senders_receive_nothing_and_change_nothing(autopilot_factory, tmp_path):
    path = key_file(tmp_path)
    ap = autopilot_factory(args=["--signing-key", path])
    intruders = [sender(ap), sender(ap, key=WRONG_KEY)]
    try:
        ap.vehicle.conn.setup_signing(KEY, sign_outgoing=True, link_id=1)
        for who in intruders:
            who.mav.heartbeat_send(6, 8, 0, 0, 0)
            who.mav.command_long_send(1, 1, 400, 0, 1, 21196, NAN, NAN, NAN, NAN, NAN)  # force-arm
            who.mav.command_long_send(1, 1, 176, 0, 1, 4, 6, NAN, NAN, NAN, NAN)  # AUTO.LAND
            who.mav.command_long_send(1, 1, REQUEST_MESSAGE, 0, AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
            who.mav.param_set_send(1, 1, b"MIS_TAKEOFF_ALT", 9.0, 9)
            who.mav.param_request_list_send(1, 1)
            who.mav.setup_signing_send(1, 1, WRONG_KEY, now_timestamp())
        for who in intruders:
            assert anything(who, 2.0) is None, "an intruder received a frame"
        # The signed ground station still gets the telemetry, and nothing moved.
        hb = ap.vehicle.wait_heartbeat(timeout=3)
        assert not gcs.telemetry.is_armed(hb) and hb.custom_mode == gcs.custom_mode("AUTO.LOITER")
        assert abs(ap.vehicle.param_get("MIS_TAKEOFF_ALT") - 2.5) < 1e-6
        assert path.read_bytes() == KEY, "the key file is unchanged"
    finally:
        for who in intruders:
            who.close()


def test_replayed_and_stale_frames_are_rejected(autopilot_factory, tmp_path):
    ap = autopilot_factory(args=["--signing-key", key_file(tmp_path)])
    replayer = sender(ap, key=KEY, link_id=7)
    try:
        request = replayer.mav.command_long_encode(1, 1, REQUEST_MESSAGE, 0, AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
        frame = request.pack(replayer.mav)
        replayer.write(frame)
        assert ack_for(replayer, REQUEST_MESSAGE) is not None, "the first copy is answered"
        replayer.write(frame)
        # A duplicate within 3 s would be answered from the cache: silence means it was dropped
        # before that, for its timestamp.
        assert ack_for(replayer, REQUEST_MESSAGE, timeout=1.5) is None, "the replay is answered"
        # A new stream (other link id) whose timestamp is two minutes old.
        stale = sender(ap, key=KEY, link_id=9)
        stale.mav.signing.timestamp = now_timestamp() - 120 * 100_000
        stale.mav.command_long_send(1, 1, REQUEST_MESSAGE, 0, AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
        assert ack_for(stale, REQUEST_MESSAGE, timeout=1.5) is None, "a stale stream is answered"
        stale.close()
        # The same stream with a fresh timestamp is still welcome.
        replayer.mav.command_long_send(1, 1, REQUEST_MESSAGE, 0, AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
        assert ack_for(replayer, REQUEST_MESSAGE) is not None
    finally:
        replayer.close()


def test_setup_signing_sets_stores_and_clears_the_key(autopilot_factory, tmp_path):
    path = tmp_path / "new.key"
    ap = autopilot_factory(args=["--signing-key", path])
    ap.vehicle.wait_armable()
    assert ap.vehicle.command_ack(400, 1.0).result == ACCEPTED, "unsigned commands work without a key"
    ap.vehicle.conn.mav.setup_signing_send(1, 1, KEY, now_timestamp())
    refused = ap.vehicle.wait("STATUSTEXT", lambda m: "SETUP_SIGNING" in m.text, 2)
    assert "disarm" in refused.text, "refused while armed"
    assert ap.vehicle.command_ack(400, 0.0).result == ACCEPTED
    ap.vehicle.conn.mav.setup_signing_send(0, 0, KEY, now_timestamp())
    with pytest.raises(gcs.LinkTimeout):
        ap.vehicle.wait("STATUSTEXT", lambda m: "Signing" in m.text, 1)  # never by broadcast
    ap.vehicle.conn.mav.setup_signing_send(1, 1, KEY, now_timestamp())
    enabled = ap.vehicle.wait("STATUSTEXT", lambda m: "Signing" in m.text, 2)
    assert enabled.text == "Signing enabled; key stored"
    assert path.read_bytes() == KEY and stat.S_IMODE(path.stat().st_mode) & 0o077 == 0
    assert ap.vehicle.command_ack(400, 1.0) is None, "unsigned commands are ignored once a key is set"
    # Unsigned frames are let through on our side: the answer to "signing off" comes unsigned.
    ap.vehicle.conn.setup_signing(KEY, sign_outgoing=True, link_id=2, allow_unsigned_callback=lambda *_: True)
    assert ap.vehicle.command_ack(400, 1.0).result == ACCEPTED and ap.vehicle.command_ack(400, 0.0).result == ACCEPTED
    # Signed with the current key, an all-zero key turns signing off and removes the file.
    ap.vehicle.conn.mav.setup_signing_send(1, 1, bytes(32), 0)
    disabled = ap.vehicle.wait("STATUSTEXT", lambda m: "Signing" in m.text, 2)
    assert disabled.text == "Signing disabled; key stored"
    assert not path.exists()
    ap.vehicle.conn.disable_signing()
    assert ap.vehicle.command_ack(400, 1.0).result == ACCEPTED, "unsigned again"


def test_the_signing_timestamp_survives_a_restart(autopilot_factory, tmp_path):
    path = key_file(tmp_path)
    ahead = now_timestamp() + 3600 * 100_000
    pathlib.Path(f"{path}.timestamp").write_text(f"{ahead}\n")
    ap = autopilot_factory(args=["--signing-key", path])
    ap.vehicle.conn.setup_signing(KEY, sign_outgoing=True, link_id=1)
    ap.vehicle.wait_heartbeat()  # a signed frame read with the key
    sent = max(ap.vehicle.conn.mav.signing.stream_timestamps.values())
    assert sent > ahead, "outgoing timestamps continue after the persisted one"
    ap.stop()
    assert int(pathlib.Path(f"{path}.timestamp").read_text()) >= sent


def test_bad_key_files_are_refused_by_name(rotorpilot, tmp_path):
    empty = tmp_path / "empty.key"
    empty.write_bytes(b"\n")
    result = rotorpilot("run", "--signing-key", str(empty), "--bind-gcs", "127.0.0.1:0",
                        "--bind-api", "127.0.0.1:0", "--duration", "1", timeout=20)
    assert result.returncode != 0 and "empty.key" in result.stderr and "empty" in result.stderr


def test_sigterm_right_after_ready_shuts_down_cleanly_and_saves_the_timestamp(autopilot_factory, tmp_path):
    # The signal handlers are installed before the ready line: a SIGTERM at once is a clean
    # shutdown (exit 0, timestamp saved), never the signal's default action (it was, 2 times in 15).
    path = key_file(tmp_path)
    for _ in range(10):
        ahead = now_timestamp() + 3600 * 100_000
        pathlib.Path(f"{path}.timestamp").write_text(f"{ahead}\n")
        ap = autopilot_factory(args=["--signing-key", path], connect=False, duration=None)  # after the ready line
        ap.proc.terminate()
        assert ap.proc.wait(timeout=10) == 0
        assert int(pathlib.Path(f"{path}.timestamp").read_text()) >= ahead
