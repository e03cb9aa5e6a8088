"""The ground-station scripts against an ArduCopter vehicle (`rotorpilot run --autopilot
ardupilot`, realistic sensors, 4x): the same command lines as against PX4, each script doing the
thing the Copter way (position setpoints in GUIDED, LOITER to hold, RTL_ALT in cm, the mission
started GUIDED → arm → AUTO, the items numbered as in the file though Copter's seqs count its
home), and a swarm that mixes both personalities."""
import math

import pytest
from test_scripts import SCRIPTS, floats_after, script, swarm

ARDUPILOT = pytest.mark.rotorpilot(autopilot="ardupilot", speedup=4)


@ARDUPILOT
def test_offboard_square_flies_in_guided_and_holds_in_loiter(autopilot):
    r = script(autopilot, "offboard_square.py", "--height", "3", "--side", "3", "--leg-time", "3")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "connected to system 1 (QUADROTOR, ArduCopter)" in r.stdout, r.stdout
    lines = r.stdout.splitlines()
    assert "GUIDED" in lines and lines[-1] == "LOITER", r.stdout
    corners = [line for line in lines if line.startswith("corner ")]
    assert len(corners) == 4
    (worst,) = floats_after(r.stdout, "max corner error:")
    assert worst < 0.5, r.stdout  # GPS-grade positions
    autopilot.vehicle.sleep(1.0)  # what the vehicle said during the script, read
    assert autopilot.vehicle.current_mode() == "LOITER"
    assert 2.5 < autopilot.vehicle.relative_altitude() < 3.5, "holds at the square's height"


@ARDUPILOT
def test_mission_plan_uploads_and_flies_on_copter(autopilot):
    r = script(autopilot, "mission.py", str(SCRIPTS / "plans" / "square.json"), "--fly", timeout=150)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "RTL_ALT = 500 cm" in r.stdout and "uploaded 7 items:" in r.stdout, r.stdout
    assert "  0: MAV_CMD_NAV_TAKEOFF" in r.stdout, r.stdout  # the caller's numbering: Copter's home slot hidden
    reached = [int(line.split()[2]) for line in r.stdout.splitlines() if line.startswith("reached item")]
    # Copter reports every item it verifies, DO_CHANGE_SPEED's included.
    assert reached == [0, 1, 2, 3, 4, 5, 6], r.stdout
    assert "landed and disarmed" in r.stdout, r.stdout
    north, east, up = floats_after(r.stdout, "final position:")
    assert math.hypot(north, east) < 1.0 and abs(up) < 0.5
    assert autopilot.vehicle.param_get("RTL_ALT") == 500


def test_swarm_script_flies_a_mixed_swarm(autopilot_factory):
    ap = autopilot_factory(count=2, autopilot=["px4", "ardupilot"], speedup=4, args=["--spacing", "4"])
    r, worst = swarm(ap, "--height", "2", "--radius", "1.5", "--side", "2", "--leg-time", "3")
    assert "2 vehicles in the air (systems 1, 2)" in r.stdout
    assert "GUIDED OFFBOARD" in r.stdout.splitlines(), r.stdout
    assert worst < 0.5, r.stdout
    assert "2 vehicles landed and disarmed" in r.stdout
