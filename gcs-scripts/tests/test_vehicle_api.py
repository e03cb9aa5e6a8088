"""The package's shape: a `Vehicle` (a link and its typed state, kept in a registry keyed by the
pymavlink connection, nothing bolted onto pymavlink's object) and an `Autopilot` (the process)
that hands one out; the top level holds the entry points, the errors and the modes; the README's
first script runs as printed against a started autopilot."""
import dataclasses
import gc
import pathlib
import re
import socket
import subprocess
import sys
import time
import weakref

import pytest

import rotorpilot_gcs as gcs
from rotorpilot_gcs import flight, link, missions, telemetry

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


@pytest.fixture
def peer():
    """A pymavlink connection to a UDP socket of this process (bound to port 0), and that socket."""
    sink = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sink.bind(("127.0.0.1", 0))
    conn = gcs.mavutil.mavlink_connection(f"udpout:127.0.0.1:{sink.getsockname()[1]}")
    yield conn, sink
    link.forget(conn)
    conn.close()
    sink.close()


def test_the_top_level_holds_the_entry_points_errors_and_modes():
    assert not issubclass(gcs.Autopilot, gcs.Vehicle), "an Autopilot hands out a Vehicle, it is not one"
    names = [n for n in gcs.__all__ if not isinstance(getattr(gcs, n), type(gcs))]
    assert len(names) <= 35, names
    for name in ("Vehicle", "Autopilot", "connect", "LinkTimeout", "CommandError", "OFFBOARD", "mode_name"):
        assert name in names, name
    assert "takeoff" not in names and "nav_waypoint" not in names, "calls live in their submodules"
    assert missions.nav_waypoint(1, 2, 3.0).z == 3.0 and gcs.missions is missions


def test_a_vehicle_holds_its_links_typed_state_and_nothing_is_set_on_the_connection(peer):
    conn, _ = peer
    before = set(vars(conn))
    vehicle = gcs.Vehicle(conn)
    assert set(vars(conn)) == before, "no attribute bolted onto pymavlink's object"
    assert dataclasses.is_dataclass(vehicle.state) and vehicle.state is link.link_state(conn)
    assert [f.name for f in dataclasses.fields(link.LinkState)][:3] == ["timeout", "started", "periodic"]
    assert vehicle.state.periodic["heartbeat"].period_s == link.HEARTBEAT_PERIOD_S
    vehicle.state.timeout = 0.2
    with pytest.raises(gcs.LinkTimeout, match="0.2 s"):
        telemetry.wait_heartbeat(conn)  # the function and the method share the state
    with pytest.raises(gcs.LinkTimeout, match="0.2 s"):
        vehicle.wait_heartbeat()


def test_vehicle_methods_are_the_module_functions_bound_to_its_connection(peer):
    conn, sink = peer
    vehicle = gcs.Vehicle(conn)
    assert gcs.Vehicle.takeoff.__doc__ == flight.takeoff.__doc__
    assert vehicle.takeoff.func is flight.takeoff and vehicle.takeoff.args == (conn,)
    sent = []
    vehicle.set_periodic("probe", 0.05, lambda: sent.append(time.monotonic()))
    time.sleep(0.5)  # the keeper thread sends it meanwhile
    vehicle.stop_periodic("probe")
    assert 6 <= len(sent) <= 12, len(sent)
    sink.settimeout(1.0)
    assert sink.recv(1024), "the GCS heartbeat went out"


def test_a_forgotten_or_dropped_connection_leaves_the_registry(peer):
    conn, _ = peer
    link.link_state(conn)
    assert any(c is conn for c, _ in link._links())
    link.forget(conn)
    assert not any(c is conn for c, _ in link._links())
    sink = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sink.bind(("127.0.0.1", 0))
    try:
        other = gcs.mavutil.mavlink_connection(f"udpout:127.0.0.1:{sink.getsockname()[1]}")
        gcs.offboard.set_setpoint(other, 0.0, 0.0, -1.0)  # a periodic stream of its own
        dropped = weakref.ref(other)
        other.close()
        del other
        for _ in range(10):
            gc.collect()
            if dropped() is None:
                break
            time.sleep(0.02)
        assert dropped() is None, "the registry holds each state only while its connection lives"
    finally:
        sink.close()


def readme_first_script():
    """The README's first Python block (A first flight with pymavlink)."""
    text = README.read_text()
    section = text[text.index("## A first flight with pymavlink"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


@pytest.mark.rotorpilot(speedup=4)
def test_the_readmes_first_script_flies_as_printed(autopilot, tmp_path):
    script = readme_first_script()
    assert 'Vehicle.connect("udpin:0.0.0.0:14550")' in script
    # The same script, on this autopilot's GCS port instead of the default one.
    path = tmp_path / "first_flight.py"
    path.write_text(script.replace("udpin:0.0.0.0:14550", autopilot.gcs))
    run = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stdout + run.stderr
    assert re.search(r"hovering 3\.\d\d m up", run.stdout) or re.search(r"hovering 2\.[6-9]\d m up", run.stdout), \
        run.stdout
    assert run.stdout.rstrip().endswith("landed and disarmed"), run.stdout
