"""Fence and rally plans over the mission protocol, driven by pymavlink on ephemeral ports: a
QGroundControl `.plan` (data/fence_rally.plan: an inclusion square of ±15 m about home, an
exclusion circle of 3 m north-west, rally points 30 m north and 60 m south) goes up as QGC's plan
managers send it (MISSION_COUNT / MISSION_REQUEST_INT / MISSION_ITEM_INT with mission_type 1 and
2, `rotorpilot_gcs.upload_mission`), comes back identical, is cleared per type and all at once; a
vehicle flown out of an inclusion fence runs GF_ACTION with its STATUSTEXT; RTL lands at a nearer
rally point."""
import pathlib

import pytest

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink
from rotorpilot_gcs.missions import ALL, FENCE, RALLY

PLAN = pathlib.Path(__file__).resolve().parent / "data" / "fence_rally.plan"
HOME = gcs.geo.DEFAULT_HOME
NAN = float("nan")


def north_of_home(metres):
    """(lat, lon) [degE7] `metres` north of home."""
    return gcs.geo.offset_to_global(HOME[0], HOME[1], metres, 0.0)


def reposition(ap, north_m, alt_m):
    """DO_REPOSITION (COMMAND_INT, GLOBAL_RELATIVE_ALT_INT) `north_m` north of home at `alt_m`."""
    ap.vehicle.conn.mav.command_int_send(1, 1, 6, 192, 0, 0, -1, 1, 0, NAN, *north_of_home(north_m), alt_m)


def test_a_qgc_plan_fence_and_rally_upload_download_and_clear(vehicle):
    assert vehicle.command_ack(512, 148).result == mavlink.MAV_RESULT_ACCEPTED
    caps = vehicle.wait("AUTOPILOT_VERSION", timeout=2).capabilities
    assert caps & mavlink.MAV_PROTOCOL_CAPABILITY_MISSION_FENCE and caps & mavlink.MAV_PROTOCOL_CAPABILITY_MISSION_RALLY
    plan = gcs.plans.load_qgc_plan(PLAN)
    assert [i.command for i in plan.fence] == [5001] * 4 + [5004] and len(plan.rally) == 2
    vehicle.upload_mission(plan.fence, FENCE)
    vehicle.upload_mission(plan.rally, RALLY)
    assert vehicle.download_mission(FENCE) == plan.fence
    assert vehicle.download_mission(RALLY) == plan.rally
    assert vehicle.download_mission() == [], "the mission is another plan"
    # A refused fence (a two-vertex polygon) leaves the stored one.
    lat, lon = north_of_home(0.0)
    bad = [gcs.missions.MissionItem(5001, lat, lon, 0.0, mavlink.MAV_FRAME_GLOBAL, 2.0, autocontinue=0)] * 2
    with pytest.raises(gcs.MissionError) as refused:
        vehicle.upload_mission(bad, FENCE)
    assert refused.value.result == mavlink.MAV_MISSION_ERROR
    text = vehicle.wait("STATUSTEXT", lambda m: "Fence item" in m.text, 2)
    assert "refused" in text.text
    assert vehicle.download_mission(FENCE) == plan.fence
    vehicle.clear_mission(FENCE)
    assert vehicle.download_mission(FENCE) == [] and vehicle.download_mission(RALLY) == plan.rally
    vehicle.clear_mission(ALL)
    assert vehicle.download_mission(RALLY) == []


@pytest.mark.rotorpilot(speedup=4)  # flights paced at 4x: the checks are in simulated time
def test_flying_out_of_an_inclusion_fence_runs_gf_action(autopilot):
    autopilot.vehicle.param_set("GF_ACTION", 3)
    autopilot.vehicle.upload_mission(gcs.plans.load_qgc_plan(PLAN).fence, FENCE)
    autopilot.vehicle.takeoff()
    reposition(autopilot, 40.0, 3.0)  # out through the fence
    breach = autopilot.vehicle.wait("STATUSTEXT", lambda m: m.text.startswith("Geofence breached"), 20)
    assert breach.text == "Geofence breached (outside inclusion zone 1)"
    assert breach.severity == mavlink.MAV_SEVERITY_CRITICAL
    autopilot.vehicle.wait_mode("AUTO.LOITER", 3)  # GF_ACTION 3: return, after COM_FAIL_ACT_T (5 s) in a hold
    autopilot.vehicle.wait_mode("AUTO.RTL", 7)
    pos = autopilot.vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert 14.0 < pos.x < 20.0, f"turned back at the fence: {pos.x:.1f} m"
    with pytest.raises(gcs.LinkTimeout):
        autopilot.vehicle.wait("STATUSTEXT", lambda m: m.text.startswith("Geofence breached"), 3)  # once


@pytest.mark.rotorpilot(speedup=4)  # flights paced at 4x: the checks are in simulated time
def test_rtl_lands_at_a_nearer_rally_point(autopilot):
    autopilot.vehicle.param_set("RTL_RETURN_ALT", 5.0)
    autopilot.vehicle.upload_mission(gcs.plans.load_qgc_plan(PLAN).rally, RALLY)
    autopilot.vehicle.takeoff()
    reposition(autopilot, 20.0, 3.0)
    autopilot.vehicle.wait("LOCAL_POSITION_NED", lambda m: abs(m.x - 20) < 0.3, 15)
    autopilot.vehicle.return_to_launch()
    autopilot.vehicle.wait_disarmed(60)  # returned, landed and disarmed
    pos = autopilot.vehicle.wait("LOCAL_POSITION_NED", timeout=2)
    assert abs(pos.x - 30) < 0.5 and abs(pos.y) < 0.5, f"at the rally point 30 m north: {pos.x:.1f}, {pos.y:.1f}"
