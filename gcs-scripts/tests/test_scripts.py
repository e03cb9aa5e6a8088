"""The ground-station scripts run as a user runs them, against the real `rotorpilot run`.

The autopilot binds its GCS port to an ephemeral port (read from its ready line) and each script
connects with ``--connection udpout:127.0.0.1:PORT``: the script's first heartbeat registers it as
a peer, exactly as a GCS on a PX4 SITL's bind port does."""
import csv
import json
import math
import os
import pathlib
import subprocess
import sys
import time

import pytest

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "gcs-scripts"
BINARY = pathlib.Path(os.environ.get("ROTORPILOT_BIN", ROOT / "target" / "release" / "rotorpilot"))
ALL_SCRIPTS = ["takeoff_land.py", "offboard_square.py", "mission.py", "set_controller.py", "log_telemetry.py",
               "live_wrench.py"]
NAN = float("nan")

sys.path.insert(0, str(SCRIPTS))
import common  # noqa: E402


class Autopilot:
    """`rotorpilot run` on ephemeral ports; `connection` is what a script passes as --connection."""

    def __init__(self, *args):
        self.proc = subprocess.Popen(
            [str(BINARY), "run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0", "--gcs", "127.0.0.1:9",
             "--api", "127.0.0.1:9", "--duration", "150", *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = json.loads(self.proc.stdout.readline())
        self.connection = f"udpout:{self.ready['gcs_bind']}"

    def script(self, name, *args, timeout=90):
        return run_script(name, "--connection", self.connection, *args, timeout=timeout)

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
        self.proc.wait(timeout=10)


def run_script(name, *args, timeout=90):
    return subprocess.run([sys.executable, str(SCRIPTS / name), *args], capture_output=True, text=True,
                          timeout=timeout, check=False)


@pytest.fixture
def autopilot(rotorpilot_bin):
    ap = Autopilot()
    yield ap
    ap.close()


def floats_after(text, label):
    """The numbers following `label` on the first line containing it."""
    line = next(line for line in text.splitlines() if label in line)
    return [float(tok.rstrip(",m")) for tok in line.split(label, 1)[1].split() if tok.rstrip(",m").lstrip("+-")
            .replace(".", "", 1).isdigit()]


@pytest.mark.parametrize("script", ALL_SCRIPTS)
def test_help_names_the_default_connection(script):
    r = run_script(script, "--help", timeout=30)
    assert r.returncode == 0, r.stderr
    assert "--connection" in r.stdout and "udpin:0.0.0.0:14550" in r.stdout


@pytest.mark.parametrize("script,extra", [("takeoff_land.py", []), ("set_controller.py", ["geometric"]),
                                          ("log_telemetry.py", ["--out", "unused.csv"])])
def test_no_autopilot_is_a_clear_timeout(script, extra, tmp_path):
    r = run_script(script, *extra, "--connection", "udpin:127.0.0.1:0", "--timeout", "1", timeout=30)
    assert r.returncode == 1
    assert r.stderr.startswith("error: no autopilot heartbeat on udpin:127.0.0.1:0 within 1 s"), r.stderr
    assert "Traceback" not in r.stderr


def test_bad_usage_exits_2():
    r = run_script("takeoff_land.py", "--height", "-3", timeout=30)
    assert r.returncode == 2 and "--height must be in (0, 1000] m" in r.stderr


def test_takeoff_land(autopilot):
    r = autopilot.script("takeoff_land.py", "--height", "2", "--hold", "1")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "connected to system 1 (QUADROTOR)" in r.stdout
    north, east, up = floats_after(r.stdout, "took off to 2 m:")
    assert abs(north) < 0.1 and abs(east) < 0.1 and abs(up - 2.0) < 0.15
    north, east, up = floats_after(r.stdout, "landed and disarmed:")
    # Positions are the centre of mass: on the ground it sits at quad_x's gear height, 0.1 m.
    assert abs(north) < 0.1 and abs(east) < 0.1 and abs(up - 0.1) < 0.05


def test_offboard_square_reaches_every_corner(autopilot):
    r = autopilot.script("offboard_square.py", "--height", "2", "--side", "2", "--leg-time", "4", "--land")
    assert r.returncode == 0, r.stdout + r.stderr
    corners = [line for line in r.stdout.splitlines() if line.startswith("corner ")]
    assert len(corners) == 4
    (worst,) = floats_after(r.stdout, "max corner error:")
    assert worst < 0.1, r.stdout
    assert "landed and disarmed" in r.stdout


def test_mission_plan_uploads_and_flies(autopilot):
    r = autopilot.script("mission.py", str(SCRIPTS / "plans" / "square.json"), "--fly", timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "RTL_RETURN_ALT = 5" in r.stdout and "uploaded 7 items:" in r.stdout
    reached = [int(line.split()[2]) for line in r.stdout.splitlines() if line.startswith("reached item")]
    assert reached == [0, 1, 2, 3, 4, 5, 6], r.stdout
    assert "landed and disarmed" in r.stdout
    north, east, up = floats_after(r.stdout, "final position:")
    assert math.hypot(north, east) < 0.3 and abs(up) < 0.15


def test_mission_plan_errors_name_the_field(tmp_path):
    plan = tmp_path / "bad.json"
    plan.write_text(json.dumps({"takeoff_alt": 3, "waypoints": [{"north": 1, "east": "x", "alt": 3}]}))
    r = run_script("mission.py", str(plan), "--connection", "udpin:127.0.0.1:0", timeout=30)
    assert r.returncode == 2
    assert r.stderr.strip() == f'error: {plan}: waypoints[0]: field "east" must be a number, not "x"'
    plan.write_text("{")
    r = run_script("mission.py", str(plan), timeout=30)
    assert r.returncode == 2 and "invalid JSON" in r.stderr


def test_set_controller_and_refusal(autopilot):
    r = autopilot.script("set_controller.py", "passivity", "--estimator-order", "3", "--compensation", "off",
                         "--gain", "PAS_KO_Z=12.5")
    assert r.returncode == 0, r.stdout + r.stderr
    for line in ("RP_CTRL = 2", "RP_EST_ORDER = 3", "RP_COMP = 0", "RP_PAS_KO_Z = 12.5"):
        assert line in r.stdout, r.stdout
    r = autopilot.script("set_controller.py", "geometric", "--gain", "GEO_KP_Z=-1")
    assert r.returncode == 1
    assert r.stderr.startswith("error: RP_GEO_KP_Z = -1.0 refused: the autopilot kept"), r.stderr
    r = autopilot.script("set_controller.py", "geometric", "--gain", "NO_SUCH_GAIN=1")
    assert r.returncode == 1 and "RP_NO_SUCH_GAIN" in r.stderr


def test_refused_command_names_the_result_and_reason(autopilot):
    conn = common.connect(autopilot.connection, 5)
    try:
        with pytest.raises(common.CommandError) as refused:
            common.set_mode(conn, common.OFFBOARD)  # no setpoints streaming
        assert refused.value.result in (1, 2)
        assert str(refused.value).startswith("MAV_CMD_DO_SET_MODE (176) refused: MAV_RESULT_")
        assert refused.value.reason, "the autopilot's STATUSTEXT explains the refusal"
    finally:
        conn.close()


def fly_with_pymavlink(autopilot, height_m):
    """Arms and takes off with a separate GCS connection; returns it (keep it alive)."""
    conn = common.connect(autopilot.connection, 5)
    common.takeoff(conn, height_m)
    return conn


def test_log_telemetry_writes_csv(autopilot, tmp_path):
    conn = fly_with_pymavlink(autopilot, 2.0)
    try:
        out = tmp_path / "telemetry.csv"
        r = autopilot.script("log_telemetry.py", "--out", str(out), "--duration", "3")
        assert r.returncode == 0, r.stdout + r.stderr
    finally:
        conn.close()
    rows = list(csv.reader(out.open()))
    assert rows[0] == ["t_wall", "msg", "t_boot", "f1", "f2", "f3", "f4", "f5", "f6"]
    kinds = [row[1] for row in rows[1:]]
    assert kinds.count("ATTITUDE") >= 30 and kinds.count("EXT_F") >= 15 and "HEARTBEAT" in kinds
    local = [row for row in rows[1:] if row[1] == "LOCAL_POSITION_NED"]
    assert local and abs(float(local[-1][5]) + 2.0) < 0.15  # z [m] NED
    mass = [float(row[3]) for row in rows[1:] if row[1] == "EXT_MASS"]
    assert len(mass) >= 15 and all(abs(m - 1.5) < 0.05 for m in mass[-5:]), mass[-5:]  # quad_x: 1.5 kg
    assert f"wrote {len(rows) - 1} rows" in r.stdout


def test_live_wrench_prints_and_plots(autopilot, tmp_path):
    conn = fly_with_pymavlink(autopilot, 2.0)
    try:
        figure = tmp_path / "wrench.png"
        r = autopilot.script("live_wrench.py", "--duration", "2", "--plot", str(figure))
        assert r.returncode == 0, r.stdout + r.stderr
    finally:
        conn.close()
    forces = [line.split() for line in r.stdout.splitlines() if " EXT_F " in line and not line.startswith("received")]
    assert len(forces) >= 10
    # Hovering with no disturbance: the estimated external force is near zero.
    assert all(abs(float(v)) < 0.5 for f in forces[-5:] for v in f[2:5]), forces[-5:]
    assert r.stdout.splitlines()[-2].startswith(f"received EXT_F {len(forces)}, EXT_T ")
    assert figure.stat().st_size > 10_000
