"""The judge of `run_mavsdk_examples.py` (`tlog_judge.py`) on tlogs written here, frame by frame,
as `rotorpilot run --log` writes them (8-byte big-endian µs, then the frame): it reads only the
vehicle's telemetry and catches what a ground station would see go wrong — a height estimate off
at rest, a landing shown under the ground, a yaw rate that stalls or spikes, a GPS failure the
telemetry never shows — naming the values; a healthy flight passes. No vehicle needed."""
import math
import struct

import pytest
from script_module import load_script

from rotorpilot_gcs import mavlink

judge = load_script("tlog_judge")
yaw = load_script("tlog_yaw")
OFFBOARD, POSCTL = judge.OFFBOARD, judge.POSCTL
T0 = 1_800_000_000.0  # wall time of the first frame [s]


class Tlog:
    """A tlog being written: the vehicle's frames (system 1) and a client's (system 245)."""

    def __init__(self, path):
        self.file = open(path, "wb")
        self.vehicle = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
        self.client = mavlink.MAVLink(None, srcSystem=245, srcComponent=190)

    def put(self, t, message, sender=None):
        """`message` at `t` s after T0 (simulated time = wall time here)."""
        frame = message.pack(sender or self.vehicle)
        self.file.write(struct.pack(">Q", int((T0 + t) * 1e6)) + frame)

    def heartbeat(self, t, armed, mode):
        """A quadrotor's HEARTBEAT: armed or not, in PX4 `mode` (custom_mode)."""
        self.put(t, mavlink.MAVLink_heartbeat_message(2, 12, 1 | (128 if armed else 0), mode, 4, 3))

    def close(self):
        """Ends the tlog."""
        self.file.close()


def boot(t):
    """time_boot_ms at `t` [s]."""
    return int(round(t * 1000))


def fly(path, rest_z=0.0, stall=None, spike=None, landed_z=None, gps_after_failure=False):
    """A flight: at rest (z `rest_z`) until armed at 1 s, OFFBOARD climbing to 2 m with a yaw rate
    of 60 °/s for 5 s from 2 s, then 0 for 3 s (yawspeed 0 during `stall` (from, to) and `spike`
    °/s at 6.5 s); a descent at 0.5 m/s from 10 s to ON_GROUND at 14 s, resting at z `landed_z`
    (default `rest_z`; relative_alt = -z), disarmed at 16 s; a GPS failure accepted at 15 s, after
    which GPS_RAW_INT goes on with a 3D fix when `gps_after_failure` and SYS_STATUS clears the GPS
    health bit; 20 s in all."""
    log = Tlog(path)
    landed_z = rest_z if landed_z is None else landed_z
    log.put(0.0, mavlink.MAVLink_extended_sys_state_message(0, 1))
    for i in range(2000):  # 100 Hz
        t = i / 100
        armed = 1.0 <= t < 16.0
        mode = OFFBOARD if 1.5 <= t < 10.0 else POSCTL
        if i % 100 == 0 or t in (1.0, 1.5, 10.0, 16.0):
            log.heartbeat(t, armed, mode)
        # The height above the rest point: climbing 1 m/s from 2 s to 4 s, descending 0.5 m/s from 10 s.
        up = 0.0 if t < 2.0 else min(t - 2.0, 2.0) if t < 10.0 else max(2.0 - 0.5 * (t - 10.0), 0.0)
        z = (rest_z if t < 12.0 else landed_z) - up
        vz = -1.0 if 2.0 <= t < 4.0 else 0.5 if 10.0 <= t < 14.0 else 0.0
        log.put(t, mavlink.MAVLink_local_position_ned_message(boot(t), 0, 0, z, 0, 0, vz))
        if i % 2 == 0:
            log.put(t, mavlink.MAVLink_global_position_int_message(boot(t), 473977420, 85455940, 488000,
                                                                   int(-z * 1000), 0, 0, int(vz * 100), 0))
        rate = 60.0 if 2.0 <= t < 7.0 else 0.0
        if stall and stall[0] <= t < stall[1]:
            rate = 0.0
        if spike and abs(t - 6.5) < 0.005:
            rate = spike
        log.put(t, mavlink.MAVLink_attitude_message(boot(t), 0, 0, 0, 0, 0, math.radians(rate)))
        if i % 5 == 0 and 1.4 <= t < 10.0:  # the client's setpoints at 20 Hz
            yaw_rate = math.radians(60.0 if 2.0 <= t < 7.0 else 0.0)
            log.put(t, mavlink.MAVLink_set_position_target_local_ned_message(
                0, 1, 1, 8, 1479, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, yaw_rate), log.client)
        if i % 10 == 0:
            failed = t >= 15.0
            if gps_after_failure or not failed:
                log.put(t, mavlink.MAVLink_gps_raw_int_message(int(t * 1e6), 3, 473977420, 85455940, 488000,
                                                               100, 100, 0, 0, 10))
            health = 0x3F ^ (32 if failed else 0)
            log.put(t, mavlink.MAVLink_sys_status_message(0x3F, 0x3F, health, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0))
        state = None
        if t == 2.0:
            state = 2  # IN_AIR
        elif t == 14.0:
            state = 1  # ON_GROUND
        if state is not None:
            log.put(t, mavlink.MAVLink_extended_sys_state_message(0, state))
        if t == 15.0:
            log.put(t, mavlink.MAVLink_command_ack_message(420, 0))
    log.close()
    return judge.Telemetry(path)


PHASES = [yaw.Phase("turn", {"vx": 0, "vy": 0, "vz": 0, "yaw_rate": 60}, 5),
          yaw.Phase("hold", {"vx": 0, "vy": 0, "vz": 0, "yaw_rate": 0}, 3)]


def failing(checks):
    """{name: values seen} of the checks that fail."""
    return {c.name: c.seen for c in checks if not c.ok}


def test_a_healthy_flight_passes_every_check(tmp_path):
    tel = fly(tmp_path / "flight.tlog")
    summary = judge.summarize(tel)
    checks = (judge.ground_checks(summary, lands=True, disarms=True) + yaw.yaw_checks(tel, PHASES))
    assert not failing(checks), failing(checks)
    assert [c.name for c in checks] == ["at rest on the ground", "disarmed on the ground", "landing 1: resting height",
                                        "landing 1: touch-down", "ends on the ground", "disarms after landing",
                                        "yaw: turn (yaw rate +60 °/s, 5 s)", "yaw: hold (yaw rate +0 °/s, 3 s)"]
    assert summary["max_height_m"] == 2.0 and summary["landings"][0]["touchdown_m_s"] == 0.5
    assert summary["landings"][0]["disarmed_after_s"] == 2.0


def test_a_height_estimate_off_at_rest_and_a_landing_under_the_ground_fail(tmp_path):
    tel = fly(tmp_path / "flight.tlog", rest_z=-0.6, landed_z=0.0)
    bad = failing(judge.ground_checks(judge.summarize(tel), lands=True))
    assert set(bad) == {"at rest on the ground", "landing 1: resting height"}, bad
    assert "LOCAL_POSITION_NED.z -0.60 m" in bad["at rest on the ground"]
    assert "-0.60 m above the rest reading" in bad["landing 1: resting height"]
    assert "shown under the ground" in bad["landing 1: resting height"]


def test_a_yaw_rate_stall_and_spike_fail_naming_the_values(tmp_path):
    tel = fly(tmp_path / "flight.tlog", stall=(4.0, 5.0), spike=220.0)
    bad = failing(yaw.yaw_checks(tel, PHASES))
    assert set(bad) == {"yaw: turn (yaw rate +60 °/s, 5 s)"}, bad
    turn = bad["yaw: turn (yaw rate +60 °/s, 5 s)"]
    assert "more than 5 °/s off for 1.00 s from +2.0 s" in turn and "stalled" in turn, turn
    assert "spike to +220.0 °/s at +4.5 s" in turn, turn


def test_a_short_glitch_passes_and_a_missing_phase_fails(tmp_path):
    tel = fly(tmp_path / "flight.tlog", stall=(4.0, 4.3))
    assert not failing(yaw.yaw_checks(tel, PHASES))
    missing = yaw.yaw_checks(tel, [yaw.Phase("climb", {"vz": -1, "yaw_rate": 0}, 4)])
    assert not missing[0].ok and "never received" in missing[0].seen


@pytest.mark.parametrize("shown", [True, False])
def test_a_gps_failure_must_show_in_the_telemetry(tmp_path, shown):
    tel = fly(tmp_path / "flight.tlog", gps_after_failure=not shown)
    checks = {c.name: c for c in judge.gps_loss_checks(tel)}
    assert checks["GPS loss shown in SYS_STATUS"].ok, checks
    raw = checks["GPS loss shown in GPS_RAW_INT"]
    assert raw.ok == shown, raw
    if not shown:
        assert "the GPS still shows a fix" in raw.seen and "fix_type 3, 10 satellites" in raw.seen, raw.seen


def test_the_heading_rate_is_read_from_the_body_rates_of_a_tilted_vehicle():
    # Turning the heading at 30 °/s pitched 30° forward: the body z rate reads cos 30° of it.
    psi_dot, theta = math.radians(30.0), math.radians(-30.0)
    attitude = mavlink.MAVLink_attitude_message(0, 0.0, theta, 0.0, -psi_dot * math.sin(theta), 0.0,
                                                psi_dot * math.cos(theta))
    assert math.isclose(judge.heading_rate(attitude), psi_dot, rel_tol=1e-6)


def test_a_commanded_heading_is_expected_to_turn_within_the_auto_rate_and_acceleration():
    # 90° from rest at 45 °/s with 0.75 s ramps at 60 °/s²: 2.75 s; 20° never reaches 45 °/s.
    turn = yaw.HeadingTurn(0.0, 0.0, 90.0)
    assert turn.duration == pytest.approx(2.75, abs=0.01)
    assert turn.rate(0.375) == pytest.approx(22.5, abs=0.1) and turn.rate(1.5) == pytest.approx(45.0)
    assert turn.rate(3.0) == 0.0
    assert max(yaw.HeadingTurn(170.0, 0.0, -170.0).rates) < 45.0
    # Still turning at +45 °/s through 118°, sent to -50°: back the short way, never the long way.
    back = yaw.HeadingTurn(118.0, 45.0, -50.0)
    assert back.turn_deg == pytest.approx(-168.0) and min(back.rates) == pytest.approx(-45.0)
    assert back.rate(0.5) > 0.0 and back.rate(1.0) < 0.0
