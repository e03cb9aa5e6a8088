"""The ground-station scripts run as a user runs them, against the real `rotorpilot run`.

The autopilot (the plugin's `autopilot` fixture) binds its GCS port to an ephemeral port (read
from its ready line) and each script connects with ``--connection udpout:127.0.0.1:PORT``: the
script's first heartbeat registers it as a peer, exactly as a GCS on a PX4 SITL's bind port does."""
import csv
import json
import math
import pathlib
import subprocess
import sys

import pytest

import rotorpilot_gcs as gcs

# The scripts are ground stations: they run against `rotorpilot run`'s default configuration
# (realistic sensors). A test of a flight's printed positions to centimetres or of an estimator's
# values flies on the exact state, marked EXACT_STATE with the reason (the realistic GPS wanders by
# decimetres); test_takeoff_land_on_realistic_sensors flies the take-off and landing on the default.
EXACT_STATE = pytest.mark.rotorpilot(sensors="ideal")

SCRIPTS = pathlib.Path(__file__).resolve().parents[1]
EXAMPLE_PLAN = SCRIPTS / "tests" / "third_party" / "mavsdk_examples" / "example-mission.plan"
ALL_SCRIPTS = ["takeoff_land.py", "offboard_square.py", "mission.py", "set_controller.py", "log_telemetry.py",
               "live_wrench.py"]


def run_script(name, *args, timeout=90):
    return subprocess.run([sys.executable, str(SCRIPTS / name), *args], capture_output=True, text=True,
                          timeout=timeout, check=False)


def script(autopilot, name, *args, timeout=90):
    """`name` run against `autopilot` (--connection to its GCS port)."""
    return run_script(name, "--connection", autopilot.gcs, *args, timeout=timeout)


def swarm(autopilot, *args, timeout=150):
    """swarm.py run against every vehicle of `autopilot` (--connection to each one's API port);
    the result and its ``max formation error`` [m]."""
    urls = [arg for v in autopilot.vehicles for arg in ("--connection", f"udpout:{v['api_bind']}")]
    r = run_script("swarm.py", "--count", str(len(autopilot.vehicles)), *urls, *args, timeout=timeout)
    assert r.returncode == 0, r.stdout + r.stderr
    (worst,) = floats_after(r.stdout, "max formation error:")
    return r, worst


def floats_after(text, label):
    """The numbers following `label` on the first line containing it."""
    line = next(line for line in text.splitlines() if label in line)
    return [float(tok.rstrip(",m")) for tok in line.split(label, 1)[1].split() if tok.rstrip(",m").lstrip("+-")
            .replace(".", "", 1).isdigit()]


@pytest.mark.parametrize("name", ALL_SCRIPTS)
def test_help_names_the_default_connection(name):
    r = run_script(name, "--help", timeout=30)
    assert r.returncode == 0, r.stderr
    assert "--connection" in r.stdout and "udpin:0.0.0.0:14550" in r.stdout


@pytest.mark.parametrize("name,extra", [("takeoff_land.py", []), ("set_controller.py", ["geometric"]),
                                        ("log_telemetry.py", ["--out", "unused.csv"])])
def test_no_autopilot_is_a_clear_timeout(name, extra, tmp_path):
    r = run_script(name, *extra, "--connection", "udpin:127.0.0.1:0", "--timeout", "1", timeout=30)
    assert r.returncode == 1
    assert r.stderr.startswith("error: no autopilot heartbeat on udpin:127.0.0.1:0 within 1 s"), r.stderr
    assert "Traceback" not in r.stderr


def test_bad_usage_exits_2():
    r = run_script("takeoff_land.py", "--height", "-3", timeout=30)
    assert r.returncode == 2 and "--height must be in (0, 1000] m" in r.stderr


@EXACT_STATE  # positions to 0.1 m, on the ground to 5 cm
def test_takeoff_land(autopilot):
    r = script(autopilot, "takeoff_land.py", "--height", "2", "--hold", "1")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "connected to system 1 (QUADROTOR)" in r.stdout
    north, east, up = floats_after(r.stdout, "took off to 2 m:")
    assert abs(north) < 0.1 and abs(east) < 0.1 and abs(up - 2.0) < 0.15
    north, east, up = floats_after(r.stdout, "landed and disarmed:")
    # Positions are the centre of mass: on the ground it sits at quad_x's gear height, 0.1 m.
    assert abs(north) < 0.1 and abs(east) < 0.1 and abs(up - 0.1) < 0.05


def test_takeoff_land_on_realistic_sensors(autopilot):
    """The default `run`: the script flies on the navigation filter's estimate (GPS-grade
    positions), takes off, holds and lands where it started."""
    r = script(autopilot, "takeoff_land.py", "--height", "2", "--hold", "1")
    assert r.returncode == 0, r.stdout + r.stderr
    north, east, up = floats_after(r.stdout, "took off to 2 m:")
    assert math.hypot(north, east) < 0.5 and abs(up - 2.0) < 0.3
    north, east, up = floats_after(r.stdout, "landed and disarmed:")
    assert math.hypot(north, east) < 0.8 and abs(up - 0.1) < 0.5


@EXACT_STATE  # every corner within 0.1 m
def test_offboard_square_reaches_every_corner(autopilot):
    r = script(autopilot, "offboard_square.py", "--height", "2", "--side", "2", "--leg-time", "4", "--land")
    assert r.returncode == 0, r.stdout + r.stderr
    corners = [line for line in r.stdout.splitlines() if line.startswith("corner ")]
    assert len(corners) == 4
    (worst,) = floats_after(r.stdout, "max corner error:")
    assert worst < 0.1, r.stdout
    assert "landed and disarmed" in r.stdout


@EXACT_STATE  # landed within 0.3 m of home and 0.15 m of the ground
def test_mission_plan_uploads_and_flies(autopilot):
    r = script(autopilot, "mission.py", str(SCRIPTS / "plans" / "square.json"), "--fly", timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "RTL_RETURN_ALT = 5" in r.stdout and "uploaded 7 items:" in r.stdout
    reached = [int(line.split()[2]) for line in r.stdout.splitlines() if line.startswith("reached item")]
    assert reached == [0, 1, 2, 3, 4, 5, 6], r.stdout
    assert "landed and disarmed" in r.stdout
    north, east, up = floats_after(r.stdout, "final position:")
    assert math.hypot(north, east) < 0.3 and abs(up) < 0.15


def test_mission_uploads_a_qgc_plan_and_a_wpl_file_as_they_are(autopilot, tmp_path):
    plan = json.loads(EXAMPLE_PLAN.read_text())
    plan["rallyPoints"]["points"] = plan["rallyPoints"]["points"][:1]
    path = tmp_path / "mission.plan"
    path.write_text(json.dumps(plan))
    r = script(autopilot, "mission.py", str(path))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "uploaded 5 items:" in r.stdout and "uploaded 1 rally items" in r.stdout, r.stdout
    expected = gcs.plans.load_qgc_plan(path)
    assert autopilot.vehicle.download_mission() == expected.mission
    assert autopilot.vehicle.download_mission(gcs.missions.RALLY) == expected.rally
    # The same mission as MAVProxy's `wp save` writes it: the home position first.
    rows = ["QGC WPL 110", "0\t1\t0\t16\t0\t0\t0\t0\t47.3977420\t8.5455940\t488.0\t1"]
    for seq, it in enumerate(expected.mission, 1):
        lat, lon = (it.x * 1e-7, it.y * 1e-7) if it.frame == 3 else (it.x, it.y)
        rows.append(f"{seq}\t0\t{it.frame}\t{it.command}\t{it.param1:g}\t{it.param2:g}\t{it.param3:g}\t"
                    f"{it.param4:g}\t{lat:.10f}\t{lon:.10f}\t{it.z:g}\t{it.autocontinue}")
    wpl = tmp_path / "mission.txt"
    wpl.write_text("\n".join(rows) + "\n")
    autopilot.vehicle.clear_mission()
    r = script(autopilot, "mission.py", str(wpl), "--wpl-skip-home")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "uploaded 5 items:" in r.stdout and "MAV_CMD_NAV_TAKEOFF: lat 47.3977632" in r.stdout, r.stdout
    assert autopilot.vehicle.download_mission() == expected.mission


def test_mission_plan_errors_name_the_field(tmp_path):
    plan = tmp_path / "bad.json"
    plan.write_text(json.dumps({"takeoff_alt": 3, "waypoints": [{"north": 1, "east": "x", "alt": 3}]}))
    r = run_script("mission.py", str(plan), "--connection", "udpin:127.0.0.1:0", timeout=30)
    assert r.returncode == 2
    assert r.stderr.strip() == f'error: {plan}: waypoints[0]: field "east" must be a number, not "x"'
    plan.write_text("{")
    r = run_script("mission.py", str(plan), timeout=30)
    assert r.returncode == 2 and "invalid JSON" in r.stderr
    plan.write_text("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t47.4\t8.5\n")
    r = run_script("mission.py", str(plan), timeout=30)
    assert r.returncode == 2 and r.stderr.strip() == f"error: {plan}:2: 10 fields, not 12"


def test_set_controller_and_refusal(autopilot):
    r = script(autopilot, "set_controller.py", "passivity", "--estimator-order", "3", "--compensation", "off",
               "--gain", "PAS_KO_Z=12.5")
    assert r.returncode == 0, r.stdout + r.stderr
    for line in ("RP_CTRL = 2", "RP_EST_ORDER = 3", "RP_COMP = 0", "RP_PAS_KO_Z = 12.5"):
        assert line in r.stdout, r.stdout
    r = script(autopilot, "set_controller.py", "geometric", "--gain", "GEO_KP_Z=-1")
    assert r.returncode == 1
    assert r.stderr.startswith("error: RP_GEO_KP_Z = -1.0 refused: the autopilot kept"), r.stderr
    r = script(autopilot, "set_controller.py", "geometric", "--gain", "NO_SUCH_GAIN=1")
    assert r.returncode == 1 and "RP_NO_SUCH_GAIN" in r.stderr


def test_refused_command_names_the_result_and_reason(autopilot):
    with pytest.raises(gcs.CommandError) as refused:
        autopilot.vehicle.set_mode("OFFBOARD")  # no setpoints streaming
    assert refused.value.result in (1, 2)
    assert str(refused.value).startswith("MAV_CMD_DO_SET_MODE (176) refused: MAV_RESULT_")
    assert refused.value.reason, "the autopilot's STATUSTEXT explains the refusal"


@EXACT_STATE  # the hover to 0.15 m and the mass estimate to 0.05 kg
def test_log_telemetry_writes_csv(autopilot, tmp_path):
    autopilot.vehicle.takeoff(2.0)
    out = tmp_path / "telemetry.csv"
    r = script(autopilot, "log_telemetry.py", "--out", str(out), "--duration", "3")
    assert r.returncode == 0, r.stdout + r.stderr
    rows = list(csv.reader(out.open()))
    assert rows[0] == ["t_wall", "msg", "t_boot", "f1", "f2", "f3", "f4", "f5", "f6"]
    kinds = [row[1] for row in rows[1:]]
    assert kinds.count("ATTITUDE") >= 30 and kinds.count("EXT_F") >= 15 and "HEARTBEAT" in kinds
    local = [row for row in rows[1:] if row[1] == "LOCAL_POSITION_NED"]
    assert local and abs(float(local[-1][5]) + 2.0) < 0.15  # z [m] NED
    mass = [float(row[3]) for row in rows[1:] if row[1] == "EXT_MASS"]
    assert len(mass) >= 15 and all(abs(m - 1.5) < 0.05 for m in mass[-5:]), mass[-5:]  # quad_x: 1.5 kg
    assert f"wrote {len(rows) - 1} rows" in r.stdout


@EXACT_STATE  # the force estimate of a still hover below 0.5 N
def test_live_wrench_prints_and_plots(autopilot, tmp_path):
    autopilot.vehicle.takeoff(2.0)
    figure = tmp_path / "wrench.png"
    r = script(autopilot, "live_wrench.py", "--duration", "2", "--plot", str(figure))
    assert r.returncode == 0, r.stdout + r.stderr
    forces = [line.split() for line in r.stdout.splitlines() if " EXT_F " in line and not line.startswith("received")]
    assert len(forces) >= 10
    # Hovering with no disturbance: the estimated external force is near zero.
    assert all(abs(float(v)) < 0.5 for f in forces[-5:] for v in f[2:5]), forces[-5:]
    assert r.stdout.splitlines()[-2].startswith(f"received EXT_F {len(forces)}, EXT_T ")
    assert figure.stat().st_size > 10_000
