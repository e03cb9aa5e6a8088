"""The package's helpers against an ArduCopter-faced vehicle (`rotorpilot run --autopilot
ardupilot`, realistic sensors), the same calls as against PX4: the personality learnt from the
HEARTBEAT, Copter's mode names (a PX4 name refused, naming both), the streams asked for on
connect, integer parameters cast, Copter's user take-off in GUIDED, LOITER, LAND and RTL as modes, a mission whose home
slot the package inserts and strips, flown in AUTO to its landing, and a mixed swarm flown with
the same calls on both vehicles. Judged from telemetry (HEARTBEAT, GLOBAL_POSITION_INT,
LOCAL_POSITION_NED, MISSION_ITEM_REACHED)."""
import pytest

from rotorpilot_gcs import mavlink
from rotorpilot_gcs.errors import ModeError
from rotorpilot_gcs.geo import offset_to_global
from rotorpilot_gcs.missions import MissionItem, nav_land, nav_takeoff, nav_waypoint
from rotorpilot_gcs.telemetry import is_armed

ARDUPILOT = pytest.mark.rotorpilot(autopilot="ardupilot", speedup=4)
GUIDED, LOITER, RTL, LAND = 4, 5, 6, 9


@ARDUPILOT
def test_takeoff_loiter_and_land_with_copter_modes(vehicle):
    assert vehicle.personality == "ardupilot"
    assert vehicle.current_mode() == "STABILIZE", "Copter boots in STABILIZE"
    with pytest.raises(ModeError, match=r"'AUTO\.MISSION' is a PX4 mode; this vehicle is ArduCopter.*GUIDED"):
        vehicle.set_mode("AUTO.MISSION")
    with pytest.raises(ModeError, match="ArduCopter"):
        vehicle.wait_mode("POSCTL")
    # Copter's integers travel cast (the number as a float), not PX4's bytes.
    assert (vehicle.param_get("RTL_ALT"), vehicle.param_get("DISARM_DELAY")) == (1500, 10)
    assert vehicle.param_set("RTL_ALT", 1200) == 1200 and vehicle.param_get("RTL_ALT") == 1200
    assert vehicle.param_set("WPNAV_SPEED", 500) == 500.0
    assert vehicle.takeoff(5) == 5.0
    hb = vehicle.wait_heartbeat()
    assert hb.custom_mode == GUIDED and is_armed(hb), "Copter's user take-off holds in GUIDED"
    vehicle.wait_in_air(5)
    assert vehicle.set_mode("LOITER").custom_mode == LOITER
    vehicle.sleep(1.0)
    assert vehicle.current_mode() == "LOITER"
    assert 4.5 < vehicle.relative_altitude() < 5.6, "holds the take-off height"
    assert vehicle.land().custom_mode == LAND
    vehicle.wait_on_ground(40)
    vehicle.wait_disarmed(20)
    assert abs(vehicle.relative_altitude()) < 0.5
    assert vehicle.current_mode() == "LAND", "Copter keeps showing the mode it landed in"


@ARDUPILOT
def test_mission_round_trip_auto_flight_and_return_to_launch(vehicle):
    lat, lon, alt = vehicle.home_position()
    north = offset_to_global(lat, lon, 12.0, 0.0)
    jump = MissionItem(mavlink.MAV_CMD_DO_JUMP, param1=1, param2=2, frame=mavlink.MAV_FRAME_MISSION)
    plan = [nav_takeoff(*offset_to_global(lat, lon, 0.0, 0.0), 4.0), nav_waypoint(*north, 4.0), jump, nav_land(*north)]
    vehicle.upload_mission(plan)
    assert vehicle.download_mission() == plan, "home inserted as item 0 and stripped again; the jump's target kept"
    # The vehicle's own numbering counts home: a raw download says so.
    conn = vehicle.conn
    conn.mav.mission_request_list_send(conn.target_system, conn.target_component, 0)
    assert vehicle.wait("MISSION_COUNT").count == len(plan) + 1
    conn.mav.mission_request_int_send(conn.target_system, conn.target_component, 3, 0)
    raw_jump = vehicle.wait("MISSION_ITEM_INT", lambda m: m.seq == 3)
    assert (raw_jump.command, raw_jump.param1) == (mavlink.MAV_CMD_DO_JUMP, 2.0), "ArduCopter's slot of item 1"
    conn.mav.mission_ack_send(conn.target_system, conn.target_component, 0, 0)
    flight = [it for it in plan if it is not jump]
    vehicle.upload_mission(flight)
    assert vehicle.download_mission() == flight
    vehicle.set_mode("AUTO")
    vehicle.arm()
    reached = vehicle.wait_item_reached(1, timeout=40)
    assert reached.seq == 2, "MISSION_ITEM_REACHED counts the home slot"
    vehicle.wait_disarmed(40)
    here = vehicle.local_position()
    assert abs(here.x - 12.0) < 1.5 and abs(here.y) < 1.5, (here.x, here.y)
    assert vehicle.current_mode() == "AUTO"
    # Take off again where it landed and come home.
    vehicle.takeoff(4)
    assert vehicle.return_to_launch().custom_mode == RTL
    vehicle.wait_disarmed(60)
    home = vehicle.local_position()
    assert abs(home.x) < 1.5 and abs(home.y) < 1.5 and abs(home.z) < 0.5, (home.x, home.y, home.z)
    assert vehicle.current_mode() == "RTL"


def test_a_mixed_swarm_flown_with_the_same_calls(autopilot_factory):
    ap = autopilot_factory(count=2, autopilot=["px4", "ardupilot"], speedup=4)
    px4, copter = ap.fleet()
    assert (px4.personality, copter.personality) == ("px4", "ardupilot")
    assert (px4.sysid, copter.sysid) == (1, 2)
    with pytest.raises(ModeError, match=r"'GUIDED' is an ArduCopter mode; this vehicle is PX4"):
        px4.set_mode("GUIDED")
    for v in (px4, copter):
        v.wait_armable()
        assert v.takeoff(4) == 4.0
    for v in (px4, copter):
        assert 3.5 < v.relative_altitude() < 4.6, v
        v.return_to_launch()
    for v in (px4, copter):
        v.wait_disarmed(60)
        assert abs(v.relative_altitude()) < 0.5
    assert copter.current_mode() == "RTL", "PX4 holds once landed, Copter keeps showing RTL"
