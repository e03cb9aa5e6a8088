"""rotorpilot-gcs as a user gets it: `pip install ./gcs-scripts` into an empty venv and a user's
mission tests run by that venv's pytest with the plugin's `autopilot` fixture; a failing test
keeps its autopilot's run directory and names it in the report; the marker's options reach the
vehicle; MAVSDK connects to `Autopilot.api`; the binary lookup order; the plan files."""
import asyncio
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

import pytest

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink

SCRIPTS = pathlib.Path(__file__).resolve().parents[1]
GUIDE = SCRIPTS.parent / "docs" / "gcs_scripts.md"

TAKEOFF_LAND_TEST = '''
import pytest


@pytest.mark.rotorpilot(speedup=5)
def test_take_off_and_land(vehicle):
    vehicle.takeoff(2.0)  # NAV_TAKEOFF, arm, in the air
    assert abs(vehicle.local_position().z + 2.0) < 0.2
    vehicle.land()  # NAV_LAND
    vehicle.wait_on_ground(timeout=30)
    assert not vehicle.wait_disarmed(timeout=10).base_mode & 128
'''

# The example of docs/gcs_scripts.md, verbatim.
GUIDE_TEST = '''import pytest
from rotorpilot_gcs.geo import offset_to_global
from rotorpilot_gcs.missions import nav_return_to_launch, nav_takeoff, nav_waypoint


@pytest.mark.rotorpilot(airframe="hexa_x", speedup=5, params={"MPC_XY_CRUISE": 4})
def test_square_mission(vehicle):
    lat, lon, _ = vehicle.home_position()
    corners = [offset_to_global(lat, lon, north, east) for north, east in [(0, 0), (5, 0), (5, 5), (0, 5)]]
    vehicle.upload_mission([nav_takeoff(*corners[0], 3.0)] + [nav_waypoint(*c, 3.0) for c in corners[1:]]
                           + [nav_return_to_launch()])
    vehicle.set_mode("AUTO.MISSION")
    vehicle.arm()
    vehicle.wait("MISSION_ITEM_REACHED", lambda m: m.seq == 3, timeout=60)  # the last corner
    vehicle.wait_disarmed(timeout=60)  # returned, landed, disarmed
    home = vehicle.local_position()
    assert abs(home.x) < 0.3 and abs(home.y) < 0.3
'''


def inner_env():
    """The environment for a pytest run inside this one (none of the outer run's settings)."""
    return {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST_", "PYTHONPATH"))}


def test_pip_install_into_an_empty_venv_and_a_users_mission_tests_fly(tmp_path, rotorpilot_bin):
    """The package's own dependencies only (pymavlink) and the `pytest` extra, at the versions
    requirements.txt pins (a constraints file; pip's cache is used)."""
    source = tmp_path / "gcs-scripts"
    shutil.copytree(SCRIPTS, source, ignore=shutil.ignore_patterns("tests", "build", "*.egg-info", "__pycache__",
                                                                   ".pytest_cache"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=120)
    python = venv / "bin" / "python"
    pip = subprocess.run([str(python), "-m", "pip", "install", "--disable-pip-version-check", "--quiet",
                          f"{source}[pytest]", "-c", str(SCRIPTS / "requirements.txt")],
                         capture_output=True, text=True, timeout=600, env=inner_env(), check=False)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    where = subprocess.run([str(python), "-c", "import rotorpilot_gcs, pathlib; p = pathlib.Path("
                            "rotorpilot_gcs.__file__).parent; print(p, (p / 'py.typed').exists())"],
                           capture_output=True, text=True, timeout=60, check=True, cwd=tmp_path)
    package, typed = where.stdout.split()
    assert pathlib.Path(package).is_relative_to(venv) and typed == "True", where.stdout
    tests = tmp_path / "user"
    tests.mkdir()
    (tests / "test_takeoff_land.py").write_text(TAKEOFF_LAND_TEST)
    (tests / "test_square_mission.py").write_text(GUIDE_TEST)
    run = subprocess.run([str(python), "-m", "pytest", "-p", "no:cacheprovider", "-rA", "--rotorpilot-bin",
                          str(rotorpilot_bin), "."], cwd=tests, capture_output=True, text=True, timeout=300,
                         env=inner_env(), check=False)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "PASSED test_takeoff_land.py::test_take_off_and_land" in run.stdout, run.stdout
    assert "PASSED test_square_mission.py::test_square_mission" in run.stdout, run.stdout


def test_the_docs_show_the_mission_test_run_here():
    assert GUIDE_TEST in GUIDE.read_text(), "docs/gcs_scripts.md's user mission test differs from GUIDE_TEST"


FAILING_TESTS = '''
import pytest


@pytest.mark.rotorpilot(log=True, speedup=5)
def test_fails_in_the_air(vehicle):
    vehicle.takeoff(2.0)
    assert vehicle.param_get("MIS_TAKEOFF_ALT") == 99, "a deliberate failure"


def test_passes(autopilot):
    assert autopilot.vehicle.param_get("MIS_TAKEOFF_ALT") == 2.5


def test_fails_at_start(autopilot_factory):
    autopilot_factory(airframe="no_such_airframe")
'''


def test_a_failing_test_keeps_its_run_directory_and_the_report_names_it(tmp_path, rotorpilot_bin):
    (tmp_path / "test_user.py").write_text(FAILING_TESTS)
    base = tmp_path / "base"
    run = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "--basetemp", str(base),
                          "--rotorpilot-bin", str(rotorpilot_bin), "test_user.py"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300, env=inner_env(), check=False)
    assert run.returncode == 1, run.stdout + run.stderr
    assert "2 failed, 1 passed" in run.stdout, run.stdout
    kept = re.findall(r"^rotorpilot run directory kept: (\S+)$", run.stdout, re.MULTILINE)
    assert len(kept) == 2, run.stdout
    flight, start = (pathlib.Path(k) for k in kept)
    assert flight.name.startswith("rotorpilot-test_fails_in_the_air"), kept
    assert json.loads((flight / "stdout.txt").read_text().splitlines()[0])["event"] == "ready"
    assert "stopped after" in (flight / "stderr.txt").read_text(), "stopped at teardown, its log kept"
    assert "--log" in (flight / "command.txt").read_text()
    assert (flight / "log" / "flight.tlog").stat().st_size > 0 and list(flight.glob("log/log/*/*.ulg"))
    assert "no_such_airframe" in (start / "stderr.txt").read_text(), "a start failure keeps its stderr"
    assert "no_such_airframe" in run.stdout, "and the report shows it"
    assert not list(base.glob("rotorpilot-test_passes*")), "a passing test's run directory is deleted"


@pytest.mark.rotorpilot(speedup=1, airframe="quad_x", controller="passivity")
class TestMarkerOptions:
    @pytest.mark.rotorpilot(airframe="hexa_x", speedup=5, params={"MPC_XY_VEL_MAX": 5, "RP_EST_ORDER": 1},
                            log=True)
    def test_reach_the_vehicle_the_closest_marker_winning(self, autopilot):
        hb = autopilot.vehicle.wait_heartbeat()
        assert hb.type == mavlink.MAV_TYPE_HEXAROTOR, "airframe hexa_x (the method's marker)"
        assert autopilot.vehicle.param_get("RP_CTRL") == 2, "controller passivity (the class's marker)"
        assert autopilot.vehicle.param_get("MPC_XY_VEL_MAX") == 5.0 and autopilot.vehicle.param_get("RP_EST_ORDER") == 1
        # Speed-up 5: five simulated seconds per wall second, from ATTITUDE's time_boot_ms.
        first = autopilot.vehicle.wait("ATTITUDE")
        start = time.monotonic()
        autopilot.vehicle.sleep(1.5)
        last = gcs.link.latest(autopilot.vehicle.conn, "ATTITUDE")
        ratio = (last.time_boot_ms - first.time_boot_ms) / 1000 / (time.monotonic() - start)
        assert 3.5 < ratio < 6.5, ratio
        assert (autopilot.log_dir / "flight.tlog").exists() and autopilot.log_dir.parent == autopilot.workdir


@pytest.mark.filterwarnings("ignore:The 'mavsdk' package has been renamed:FutureWarning",
                            "ignore:path is deprecated:DeprecationWarning")
def test_mavsdk_connects_to_the_api_address(autopilot):
    from mavsdk import System

    async def fly():
        drone = System(port=gcs.free_port())
        await drone.connect(system_address=autopilot.api)
        try:
            async for state in drone.core.connection_state():
                if state.is_connected:
                    break
            await drone.action.set_takeoff_altitude(3.0)
            return await drone.param.get_param_float("MIS_TAKEOFF_ALT")
        finally:
            drone._stop_mavsdk_server()  # the mavsdk_server System.connect started

    assert autopilot.api.startswith("udpout://127.0.0.1:")
    assert asyncio.run(asyncio.wait_for(fly(), 60)) == 3.0
    assert autopilot.vehicle.param_get("MIS_TAKEOFF_ALT") == 3.0


def test_the_binary_is_the_option_then_the_environment_then_the_packaged_one_then_path(tmp_path, monkeypatch):
    for name in ("option", "env", "packaged", "checkout", "path"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "rotorpilot").write_text("#!/bin/sh\n")
        (tmp_path / name / "rotorpilot").chmod(0o755)
    monkeypatch.setenv("PATH", str(tmp_path / "path"))
    monkeypatch.setenv("ROTORPILOT_BIN", str(tmp_path / "env" / "rotorpilot"))
    monkeypatch.setattr(gcs.process, "packaged_binary", lambda: tmp_path / "packaged" / "rotorpilot")
    checkout = tmp_path / "checkout" / "rotorpilot"
    assert gcs.find_binary(tmp_path / "option" / "rotorpilot") == tmp_path / "option" / "rotorpilot"
    assert gcs.find_binary() == tmp_path / "env" / "rotorpilot"
    monkeypatch.delenv("ROTORPILOT_BIN")
    assert gcs.find_binary(fallback=checkout) == tmp_path / "packaged" / "rotorpilot"
    monkeypatch.setattr(gcs.process, "packaged_binary", lambda: None)  # an editable install
    assert gcs.find_binary(fallback=checkout) == checkout
    assert gcs.find_binary() == tmp_path / "path" / "rotorpilot"
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(FileNotFoundError, match="--rotorpilot-bin"):
        gcs.find_binary()
    with pytest.raises(FileNotFoundError, match="nowhere"):
        gcs.find_binary(tmp_path / "nowhere")


def test_plan_files(tmp_path):
    example = gcs.plans.load_qgc_plan(SCRIPTS / "tests" / "third_party" / "mavsdk_examples" / "example-mission.plan")
    assert [(i.command, i.frame) for i in example.mission] == [(22, 3), (16, 3), (16, 3), (16, 3), (20, 2)]
    assert example.mission[0].x == round(47.397763168426465 * 1e7) and example.mission[0].z == 50
    assert len(example.rally) == 2 and example.fence == []
    wpl = tmp_path / "mission.txt"
    wpl.write_text("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t47.397742\t8.545594\t488\t1\n"
                   "1\t0\t3\t22\t0\t0\t0\t0\t47.3978\t8.5456\t5\t1\n")
    (item,) = gcs.plans.load_wpl(wpl, skip_home=True)
    assert item == gcs.missions.MissionItem(22, 473978000, 85456000, 5.0, 3)
    assert item == gcs.missions.MissionItem(22, 473978000, 85456000, 5.0 + 1e-9, 3), "compared as float32"
    assert gcs.missions.nav_waypoint(1, 2, 3.0) == gcs.missions.nav_waypoint(1, 2, 3.0), "NaN yaw equal to NaN yaw"
    wpl.write_text("QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t47.39\t8.54\t488\tx\n")
    with pytest.raises(gcs.UsageError, match=r"mission.txt:2: invalid literal"):
        gcs.plans.load_wpl(wpl)
    bad = tmp_path / "bad.plan"
    bad.write_text(json.dumps({"fileType": "Plan", "mission": {"items": [{"type": "ComplexItem",
                                                                          "complexItemType": "survey"}]}}))
    with pytest.raises(gcs.UsageError, match=r"mission.items\[0\]: only SimpleItems are supported, not survey"):
        gcs.plans.load_qgc_plan(bad)


def test_parameter_bits_and_modes():
    assert gcs.params.float_bits_to_int(gcs.params.int32_bits(-123456)) == -123456
    assert gcs.custom_mode("auto.rtl") == gcs.custom_mode(4, 5) == (4 << 16) | (5 << 24)
    assert gcs.mode_name(gcs.custom_mode("OFFBOARD")) == "OFFBOARD" and gcs.mode_name(9 << 16) == "mode 9/0"
    with pytest.raises(ValueError, match="unknown PX4 mode 'CRUISE'"):
        gcs.parse_mode("CRUISE")


def test_waiting_on_one_link_keeps_every_links_streams_going():
    """A swarm script waits on one vehicle at a time: the other vehicles' setpoint streams (and
    GCS heartbeats) must go on meanwhile, or their offboard is lost after COM_OF_LOSS_T."""
    import socket

    from rotorpilot_gcs import link

    peers = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(2)]
    conns = []
    try:
        for s in peers:
            s.bind(("127.0.0.1", 0))
            conns.append(gcs.mavutil.mavlink_connection(f"udpout:127.0.0.1:{s.getsockname()[1]}"))
        sent = []
        link.set_periodic(conns[1], "setpoint", 0.05, lambda: sent.append(time.monotonic()))
        link.recv(conns[0], 1.0)  # nothing answers on link 0: a full second of waiting
        assert len(sent) >= 15, f"link 1's 20 Hz stream sent {len(sent)} times in 1 s of waiting on link 0"
        assert max(b - a for a, b in zip(sent, sent[1:])) < 0.2
        link.forget(conns[1])
        conns[1].close()
        link.recv(conns[0], 0.2)  # a forgotten, closed link is left alone
    finally:
        for c in conns:
            c.close()
        for s in peers:
            s.close()
