"""The autopilot's failsafes as a ground station sees them: the GCS link lost (NAV_DLL_ACT), a
draining battery (COM_LOW_BAT_ACT), a motor failure injected (COM_ACT_FAIL_ACT); each announced
by STATUSTEXT and shown in the heartbeat's mode. On `rotorpilot run`'s default configuration
(realistic sensors), as test_autopilot_link.py's link behaviours."""
import math
import time

import pytest

from rotorpilot_gcs import custom_mode, mavlink

ACCEPTED, DENIED = mavlink.MAV_RESULT_ACCEPTED, mavlink.MAV_RESULT_DENIED


def test_gcs_link_loss_returns_to_launch(vehicle):
    vehicle.set_heartbeats(False)
    for name, value in [("NAV_DLL_ACT", 2), ("COM_DL_LOSS_T", 5)]:
        vehicle.param_set(name, value)
    vehicle.send_heartbeat()  # one GCS heartbeat, then silence
    assert vehicle.command_ack(22).result == ACCEPTED
    vehicle.wait_armable()
    assert vehicle.command_ack(400, 1.0).result == ACCEPTED
    lost = vehicle.wait("STATUSTEXT", lambda m: "link lost" in m.text, 9)
    assert "returning" in lost.text
    # COM_FAIL_ACT_T (5 s) in a hold first, as PX4; a take-off still climbing (PX4's take-off
    # speed) climbs on into its own hold.
    vehicle.wait_mode("AUTO.LOITER", 5)
    vehicle.wait_mode("AUTO.RTL", 7)


def test_battery_failsafe_announces_and_changes_mode(vehicle):
    """A small pack: BATTERY_STATUS drains, the failsafes announce themselves (critical
    STATUSTEXT) and the heartbeat shows the COM_FAIL_ACT_T hold (AUTO.LOITER), then AUTO.LAND
    (the emergency level comes within the critical level's hold: the waiting return becomes a
    landing)."""
    vehicle.param_set("BAT1_CAPACITY", 300.0)
    vehicle.param_set("COM_LOW_BAT_ACT", 3)
    full = vehicle.wait("BATTERY_STATUS", timeout=3)
    assert full.battery_remaining == 100 and full.voltages[:3] == [4200] * 3 and full.voltages[3] == 65535
    assert vehicle.command_ack(22).result == ACCEPTED
    vehicle.wait_armable()
    assert vehicle.command_ack(400, 1.0).result == ACCEPTED
    texts, modes = [], []
    deadline = time.monotonic() + 25
    while time.monotonic() < deadline and len(texts) < 3:
        m = vehicle.recv(0.5)
        if m is None:
            continue
        if m.get_type() == "STATUSTEXT" and "battery" in m.text.lower():
            texts.append((m.severity, m.text))
        elif m.get_type() == "HEARTBEAT" and m.get_srcComponent() == 1 and m.custom_mode not in modes:
            modes.append(m.custom_mode)
    assert [t for _, t in texts] == ["Low battery: 15% remaining", "Critical battery (7%): returning",
                                     "Emergency battery (5%): landing"], texts
    assert all(severity == mavlink.MAV_SEVERITY_CRITICAL for severity, _ in texts)
    vehicle.wait_mode("AUTO.LAND", 8)
    assert custom_mode("AUTO.LOITER") in modes, "the hold shown before AUTO.LAND"
    low = vehicle.wait("BATTERY_STATUS", timeout=3)
    assert low.battery_remaining <= 5 and low.current_consumed > 280 and low.voltages[0] < 3550


@pytest.mark.rotorpilot(airframe="octo")
def test_motor_failure_injection_with_com_act_fail_act_2_lands_the_octocopter(vehicle):
    """MAV_CMD_INJECT_FAILURE (motor 3 off) needs SYS_FAILURE_EN; the octocopter announces the
    failure and shows motor 3 stopped (900 µs) in ACTUATOR_OUTPUT_STATUS, the others running;
    COM_ACT_FAIL_ACT 2 (without the COM_FAIL_ACT_T hold) shows AUTO.LAND in its heartbeat, lands
    where it was and disarms."""
    vehicle.param_set("SYS_FAILURE_EN", 0)
    assert vehicle.command_ack(420, 101, 1, 3).result == DENIED, "SYS_FAILURE_EN = 0"
    vehicle.param_set("SYS_FAILURE_EN", 1)
    vehicle.param_set("COM_ACT_FAIL_ACT", 2)
    vehicle.param_set("COM_FAIL_ACT_T", 0)
    vehicle.takeoff()
    assert vehicle.command_ack(420, 101, 1, 3).result == ACCEPTED
    text = vehicle.wait("STATUSTEXT", lambda m: m.text.startswith("Motor 3 failed"), 3)
    assert text.text == "Motor 3 failed: landing" and text.severity == mavlink.MAV_SEVERITY_CRITICAL
    actuators = vehicle.wait("ACTUATOR_OUTPUT_STATUS", lambda m: m.actuator[2] <= 901, 3)
    assert all(a >= 1000 for i, a in enumerate(actuators.actuator[:8]) if i != 2), list(actuators.actuator[:8])
    vehicle.wait_mode("AUTO.LAND", 3)
    vehicle.wait("STATUSTEXT", lambda m: "Disarmed" in m.text, 20)
    actuators = vehicle.wait("ACTUATOR_OUTPUT_STATUS", timeout=3)
    assert list(actuators.actuator[:8]) == [900.0] * 8, "disarmed: every motor stopped"
    pos = vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert math.hypot(pos.x, pos.y) < 0.5, "landed where it was"
