"""`rotorpilot run` as a child process on free ports, with a GCS connection to it: `Autopilot`.

The process binds port 0 for its GCS and API links and prints one JSON line when ready, with the
ports it bound (``{"event":"ready","sysid":1,"gcs_bind":"127.0.0.1:PORT","api_bind":...}``), so
any number of them run side by side. Its GCS telemetry goes to a pymavlink socket of this
process (`Autopilot.vehicle`); its API telemetry to a socket that only swallows it (MAVSDK connects
itself with `Autopilot.api`). Everything it writes goes to its run directory: ``command.txt``,
``stdout.txt``, ``stderr.txt``, ``params.txt`` and, with ``log=True``, ``log/`` (``flight.tlog``
and a ULog per arming); by default it writes no log (``--no-log``), so nothing lands in the
user's state directory where ``rotorpilot run`` keeps its flight logs unless told otherwise.
"""
from __future__ import annotations

import json
import math
import numbers
import os
import pathlib
import shlex
import shutil
import socket
import subprocess
import tempfile
import time
from typing import Any, Mapping, Sequence

from . import link
from ._mav import mavlink, mavutil
from .errors import AutopilotStartError, UsageError
from .link import DEFAULT_TIMEOUT, GCS_COMPONENT, GCS_SYSTEM
from .vehicle import Vehicle

#: The environment variable naming the binary.
ENV_BIN = "ROTORPILOT_BIN"
#: The process stops itself after this many wall-clock seconds (``--duration``), should the
#: test harness die without stopping it.
DEFAULT_DURATION_S = 900.0
#: Time for the process to print its ready line [s].
READY_TIMEOUT_S = 30.0
#: Time for the process to stop after SIGTERM before it is killed [s].
STOP_TIMEOUT_S = 10.0


def checkout_binary() -> pathlib.Path:
    """``target/release/rotorpilot`` of the checkout this package lives in (the scripts' default
    when run from a checkout; it may not be built)."""
    return pathlib.Path(__file__).resolve().parents[2] / "target" / "release" / "rotorpilot"


def packaged_binary() -> pathlib.Path | None:
    """The binary a wheel of this package ships (``rotorpilot_gcs/bin/rotorpilot``, built by
    ``pip install ./gcs-scripts``), or None (an editable install, ``ROTORPILOT_SKIP_BINARY=1``)."""
    path = pathlib.Path(__file__).resolve().parent / "bin" / "rotorpilot"
    return path if path.is_file() else None


def find_binary(explicit: str | os.PathLike[str] | None = None,
                fallback: str | os.PathLike[str] | None = None) -> pathlib.Path:
    """The rotorpilot binary: `explicit` if given, else ``$ROTORPILOT_BIN``, else the one this
    package ships (`packaged_binary`), else `fallback` if given (the scripts pass
    `checkout_binary()`), else ``rotorpilot`` on PATH. `FileNotFoundError` naming what was tried."""
    packaged = packaged_binary()
    if explicit:
        path, source = pathlib.Path(explicit), "the given path"
    elif os.environ.get(ENV_BIN):
        path, source = pathlib.Path(os.environ[ENV_BIN]), f"${ENV_BIN}"
    elif packaged is not None:
        return packaged
    elif fallback:
        path, source = pathlib.Path(fallback), "the checkout's build"
    else:
        found = shutil.which("rotorpilot")
        if found is None:
            raise FileNotFoundError(f"no rotorpilot binary: pass --rotorpilot-bin PATH, set ${ENV_BIN}, install "
                                    "this package from a checkout (pip install ./gcs-scripts builds and ships it), "
                                    "or put rotorpilot on PATH (cargo install --path . --locked)")
        return pathlib.Path(found)
    if not path.is_file():
        raise FileNotFoundError(f"rotorpilot binary not found at {path} ({source}): run cargo build --release first")
    return path


def free_port() -> int:
    """A TCP port free right now on 127.0.0.1 (for a server that cannot bind port 0 itself, such
    as mavsdk_server's gRPC port: ``System(port=free_port())``)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _consecutive_udp_sockets(count: int) -> list[socket.socket]:
    """`count` UDP sockets bound to consecutive free ports of 127.0.0.1."""
    for _ in range(50):
        socks: list[socket.socket] = []
        try:
            for i in range(count):
                s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
                socks.append(s)
                s.bind(("127.0.0.1", socks[0].getsockname()[1] + i if i else 0))
            return socks
        except (OSError, OverflowError):
            for s in socks:
                s.close()
    raise AutopilotStartError(f"no {count} consecutive free UDP ports on 127.0.0.1")


def _params_file(path: pathlib.Path, params: Mapping[str, float]) -> None:
    """``NAME VALUE`` lines (what ``--params`` reads; the autopilot knows each one's type)."""
    lines: list[str] = []
    for name, value in params.items():
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise UsageError(f"params: {name} = {value!r} is not a finite number")
        text = str(int(value)) if isinstance(value, numbers.Integral) else repr(float(value))
        lines.append(f"{name} {text}\n")
    path.write_text("".join(lines))


def _tail(path: pathlib.Path, lines: int) -> str:
    try:
        return "\n".join(path.read_text(errors="replace").splitlines()[-lines:])
    except OSError:
        return ""


class Autopilot:
    """A running ``rotorpilot run``: the process, its run directory and ports; start one with
    `Autopilot.start` (or the pytest fixtures ``autopilot`` / ``autopilot_factory``). It hands out
    the `Vehicle` it flies, `vehicle` (a GCS connection to it, made at start), with every
    helper as a method (``autopilot.vehicle.takeoff(3.0)``)."""

    def __init__(self, proc: subprocess.Popen[bytes], ready: dict[str, Any], workdir: pathlib.Path,
                 vehicle: Vehicle, sinks: list[socket.socket], log_dir: pathlib.Path | None, argv: list[str]) -> None:
        self.proc = proc
        self.ready = ready
        self.workdir = workdir
        self.log_dir = log_dir
        self.argv = argv
        self._vehicle = vehicle
        self._sinks = sinks
        #: The swarm's vehicles connected on their own GCS links (`vehicle_at`), by index.
        self._fleet: dict[int, Vehicle] = {}

    @property
    def vehicle(self) -> Vehicle:
        """The (first) vehicle over the GCS connection this process sends its telemetry to."""
        return self._vehicle

    def vehicle_at(self, index: int, timeout: float | None = None) -> Vehicle:
        """Vehicle `index` of the process (0, 1 … in the order of `vehicles`), connected as
        `Vehicle.connect` connects (its personality's streams asked for). With one vehicle, index 0
        is `vehicle`. In a swarm (``count`` > 1) each vehicle gets a GCS connection of its own to
        its bind port (``udpout:gcs_bind``), made on first use and closed by `stop`: the socket
        every vehicle sends its telemetry to answers whichever vehicle spoke last, so it cannot
        command one of several."""
        entries = self.vehicles
        if len(entries) <= 1 and index == 0:
            return self._vehicle
        if index not in self._fleet:
            entry = entries[index]
            wait = self._vehicle.state.timeout if timeout is None else timeout
            vehicle = Vehicle.connect(f"udpout:{entry['gcs_bind']}", wait, target_system=int(entry["sysid"]),
                                      quiet=True)
            vehicle.state.timeout = self._vehicle.state.timeout
            self._fleet[index] = vehicle
        return self._fleet[index]

    def fleet(self, timeout: float | None = None) -> list[Vehicle]:
        """Every vehicle of the process (`vehicle_at` of each), in order."""
        return [self.vehicle_at(i, timeout) for i in range(len(self.vehicles))]

    @classmethod
    def start(cls, binary: str | os.PathLike[str] | None = None, *, airframe: str | os.PathLike[str] | None = None,
              controller: str | None = None, speedup: float | str | None = None,
              params: Mapping[str, float] | None = None, log: bool | str | os.PathLike[str] | None = False,
              log_profile: str | None = None, count: int = 1, sensors: str | None = None,
              autopilot: str | Sequence[str] | None = None, args: Sequence[str] = (),
              env: Mapping[str, str] | None = None,
              duration: float | None = DEFAULT_DURATION_S, connect: bool = True, timeout: float = DEFAULT_TIMEOUT,
              workdir: str | os.PathLike[str] | None = None) -> Autopilot:
        """Starts ``rotorpilot run`` (`binary`: see `find_binary`) and waits for its ready line.

        `airframe` (preset name or TOML path), `controller` (geometric, hierarchical, passivity),
        `speedup` (simulated seconds per wall second, or ``"max"``), `count` (vehicles in the
        process, sysid counting up), `sensors` (None, the default: the binary's own default,
        realistic, as a ground station meets the vehicle: IMU, GPS, barometer and magnetometer
        through the navigation filter; ``"ideal"``: the exact state, armable at once, for a check
        of something other than what a ground station sees, such as a controller's precision) and
        `log_profile` are its options of the same name; `autopilot` is the personality,
        ``"px4"`` (the binary's default) or ``"ardupilot"`` (ArduCopter's face: Copter modes,
        GUIDED, streams only on request), or one per vehicle (``["px4", "ardupilot"]``);
        `params` sets parameters at start (``{"MPC_XY_VEL_MAX": 5}``, through ``--params``);
        `log`: False (the default here) passes ``--no-log``, so a scripted run leaves no log
        behind; True writes ``--log`` into the run directory's ``log/``; a directory: ``--log``
        there; None: the binary's own default, the flight logs in the per-user state directory
        (``$XDG_STATE_HOME/rotorpilot/instance-K``), named by the ready line's ``log_dir``, which
        becomes `log_dir`; `env` sets environment variables of the process over this one's
        (``{"XDG_STATE_HOME": dir}`` moves that state directory);
        `args` are more options (``["--signing-key", path]``); `duration` stops it
        after that many wall seconds (None: never). `connect` waits up to `timeout` [s] for the
        first heartbeat on `vehicle`'s connection. `workdir` is the run directory (default: a new temporary one).
        `AutopilotStartError` when it does not start (its stderr in the message)."""
        path = find_binary(binary)
        if workdir is None:
            run_dir = pathlib.Path(tempfile.mkdtemp(prefix="rotorpilot-"))
        else:
            run_dir = pathlib.Path(workdir)
            run_dir.mkdir(parents=True, exist_ok=True)
        argv = [str(path), "run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0"]
        if airframe is not None:
            argv += ["--airframe", str(airframe)]
        if controller is not None:
            argv += ["--controller", controller]
        if speedup is not None:
            argv += ["--speedup", speedup if isinstance(speedup, str) else f"{speedup:g}"]
        if params:
            if "--params" in args:
                raise UsageError("give parameters either as params or as --params in args, not both")
            _params_file(run_dir / "params.txt", params)
            argv += ["--params", str(run_dir / "params.txt")]
        log_dir = None
        if "--log" in args or "--no-log" in args:
            raise UsageError("give the log directory as log, not as --log or --no-log in args")
        if log is False:
            argv += ["--no-log"]
        elif log is not None:
            log_dir = run_dir / "log" if log is True else pathlib.Path(log)
            argv += ["--log", str(log_dir)]
        if log_profile is not None:
            argv += ["--log-profile", log_profile]
        if count != 1:
            argv += ["--count", str(count)]
        if "--sensors" in args:
            raise UsageError("give the sensor model as sensors, not as --sensors in args")
        if sensors is not None:
            argv += ["--sensors", sensors]
        if "--autopilot" in args:
            raise UsageError("give the personality as autopilot, not as --autopilot in args")
        if autopilot is not None:
            argv += ["--autopilot", autopilot if isinstance(autopilot, str) else ",".join(autopilot)]
        if duration is not None:
            argv += ["--duration", f"{duration:g}"]
        conn = mavutil.mavlink_connection("udpin:127.0.0.1:0", source_system=GCS_SYSTEM, source_component=GCS_COMPONENT)
        sinks: list[socket.socket] = []
        proc = None
        try:
            sinks = _consecutive_udp_sockets(count)
            argv += ["--gcs", f"127.0.0.1:{conn.port.getsockname()[1]}",
                     "--api", f"127.0.0.1:{sinks[0].getsockname()[1]}", *map(str, args)]
            (run_dir / "command.txt").write_text(shlex.join(argv) + "\n")
            with open(run_dir / "stdout.txt", "wb") as out, open(run_dir / "stderr.txt", "wb") as err:
                proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                        env=None if env is None else {**os.environ, **env})
            ready = cls._ready_line(proc, run_dir, argv)
            if log is None and ready.get("log_dir"):
                log_dir = pathlib.Path(ready["log_dir"])
            conn.target_system, conn.target_component = int(ready["sysid"]), mavlink.MAV_COMP_ID_AUTOPILOT1
            vehicle = Vehicle(conn)
            vehicle.state.timeout = timeout
            ap = cls(proc, ready, run_dir, vehicle, sinks, log_dir, argv)
            if connect:
                link.connect(conn, timeout, target_system=ap.sysid)
            return ap
        except BaseException:
            if proc is not None and proc.poll() is None:
                proc.kill()
                proc.wait()
            link.forget(conn)
            conn.close()
            for s in sinks:
                s.close()
            raise

    @staticmethod
    def _ready_line(proc: subprocess.Popen[bytes], run_dir: pathlib.Path, argv: list[str]) -> dict[str, Any]:
        """The JSON ready line the process prints first on stdout."""
        deadline = time.monotonic() + READY_TIMEOUT_S
        stdout = run_dir / "stdout.txt"
        while True:
            text = stdout.read_bytes()
            if b"\n" in text:
                line = text.split(b"\n", 1)[0].decode(errors="replace")
                break
            code = proc.poll()
            if code is not None or time.monotonic() > deadline:
                if code is None:
                    proc.kill()
                    proc.wait()
                why = f"exited with status {code}" if code is not None else f"printed nothing in {READY_TIMEOUT_S:g} s"
                raise AutopilotStartError(f"rotorpilot run {why} before its ready line ({shlex.join(argv)}); "
                                          f"stderr:\n{_tail(run_dir / 'stderr.txt', 20)}")
            time.sleep(0.01)
        try:
            ready = json.loads(line)
        except json.JSONDecodeError:
            ready = None
        if not isinstance(ready, dict) or ready.get("event") != "ready":
            raise AutopilotStartError(f"rotorpilot run printed {line!r}, not its ready line")
        return ready

    def __repr__(self) -> str:
        return (f"Autopilot(sysid={self.ready.get('sysid')}, gcs={self.gcs!r}, api={self.api!r}, pid={self.proc.pid}, "
                f"workdir={str(self.workdir)!r})")

    @property
    def sysid(self) -> int:
        """The (first) vehicle's MAVLink system id."""
        return int(self.ready["sysid"])

    @property
    def gcs_bind(self) -> str:
        """``HOST:PORT`` the (first) vehicle's GCS link is bound to."""
        return str(self.ready["gcs_bind"])

    @property
    def api_bind(self) -> str:
        """``HOST:PORT`` the (first) vehicle's API link is bound to."""
        return str(self.ready["api_bind"])

    @property
    def gcs(self) -> str:
        """A pymavlink connection string to the vehicle's GCS link (``udpout:127.0.0.1:PORT``): a
        script's or QGroundControl-like client's first heartbeat makes it a peer that gets the
        telemetry."""
        return f"udpout:{self.gcs_bind}"

    @property
    def api(self) -> str:
        """A MAVSDK system address of the vehicle's API link (``udpout://127.0.0.1:PORT``), for
        ``await System(port=free_port()).connect(system_address=autopilot.api)``."""
        return f"udpout://{self.api_bind}"

    @property
    def vehicles(self) -> list[dict[str, Any]]:
        """Each vehicle's entry of the ready line (sysid, gcs_bind, api_bind, gcs, api)."""
        return list(self.ready["vehicles"])

    @property
    def stdout_path(self) -> pathlib.Path:
        """The process's stdout (the ready line)."""
        return self.workdir / "stdout.txt"

    @property
    def stderr_path(self) -> pathlib.Path:
        """The process's stderr (its log lines)."""
        return self.workdir / "stderr.txt"

    def stderr_text(self) -> str:
        """What the process wrote on stderr so far."""
        return self.stderr_path.read_text(errors="replace")

    def stdout_text(self) -> str:
        """What the process wrote on stdout so far."""
        return self.stdout_path.read_text(errors="replace")

    def flight_logs(self) -> list[pathlib.Path]:
        """The ULog flight logs in `log_dir` (``log=True``, a directory, or the default place of
        ``log=None``; one per arming, oldest first; PX4's ``log/YYYY-MM-DD/HH_MM_SS.ulg``)."""
        return sorted(self.log_dir.glob("log/*/*.ulg")) if self.log_dir is not None else []

    @property
    def returncode(self) -> int | None:
        """The exit status once the process has ended, else None."""
        return self.proc.poll()

    def stop(self, timeout: float = STOP_TIMEOUT_S) -> int:
        """Stops the process (SIGTERM, SIGKILL after `timeout` [s]) and closes the sockets;
        returns its exit status (0: a clean shutdown). Stopping again returns it again."""
        if self.proc.poll() is None:
            self.proc.terminate()
        try:
            code = self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            code = self.proc.wait()
        self._vehicle.close()
        for vehicle in self._fleet.values():
            vehicle.close()
        self._fleet = {}
        for s in self._sinks:
            s.close()
        self._sinks = []
        return code

    def remove_workdir(self) -> None:
        """Deletes the run directory (stop first)."""
        shutil.rmtree(self.workdir, ignore_errors=True)

    def __enter__(self) -> Autopilot:
        return self

    def __exit__(self, kind: object, value: object, traceback: object) -> None:
        """Stops the process; the run directory is deleted unless an exception is on its way."""
        self.stop()
        if kind is None:
            self.remove_workdir()
