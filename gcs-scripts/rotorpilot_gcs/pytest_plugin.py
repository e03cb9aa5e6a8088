"""pytest plugin of rotorpilot-gcs (entry point ``pytest11``: active wherever the package is
installed). Fixtures:

- ``autopilot``: a started ``rotorpilot run`` (`Autopilot`) for one test, connected; its options
  from the test's ``@pytest.mark.rotorpilot(...)`` marker (the keyword arguments of
  `Autopilot.start`: ``airframe``, ``controller``, ``speedup``, ``params``, ``log``, ``args``...;
  markers on the class or module apply too, the closest winning per option).
- ``vehicle``: the ``autopilot`` fixture's `Vehicle` (``autopilot.vehicle``), the link a test
  flies with: ``vehicle.takeoff(3.0)``, ``vehicle.wait("HEARTBEAT")``...
- ``autopilot_factory``: ``autopilot_factory(**options)`` starts another one (same options), for
  tests that need several, or options computed in the test (a file in ``tmp_path``).
- ``rotorpilot_bin``: the binary: ``--rotorpilot-bin PATH``, else ``$ROTORPILOT_BIN``, else the
  one the package ships (``pip install ./gcs-scripts`` builds it in), else ``rotorpilot`` on PATH
  (the test fails naming them when none is found).
- ``rotorpilot``: ``rotorpilot(*args, timeout=120)`` runs the binary; the CompletedProcess.

Every autopilot is stopped after its test. Its run directory (``command.txt``, ``stdout.txt``,
``stderr.txt``, ``params.txt``, ``log/``, ``state/``) is deleted when the test passes and kept when it
fails: the failure report names it (section "rotorpilot run kept") with the end of its stderr.
``--rotorpilot-keep`` keeps every run directory. They live under pytest's ``--basetemp``.
Nothing is written into the user's home: an autopilot writes no log unless asked (``log``), its
per-user state directory (``log=None``: ``rotorpilot run``'s default place) is the run
directory's ``state/``, and the binary that ``rotorpilot`` runs keeps its state under pytest's
temporary directory too.
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any, Callable, Iterator

import pytest

from .process import Autopilot, find_binary
from .vehicle import Vehicle

_RUNS = pytest.StashKey[list["_Run"]]()
_FAILED = pytest.StashKey[bool]()
MARKER = "rotorpilot"
STDERR_LINES = 15


class _Run:
    """One autopilot a test started (or tried to): its run directory and, once started, it."""

    def __init__(self, workdir: Path) -> None:
        self.workdir = workdir
        self.autopilot: Autopilot | None = None

    def describe(self) -> str:
        lines = [f"rotorpilot run directory kept: {self.workdir}"]
        command = self.workdir / "command.txt"
        if command.exists():
            lines.append(f"  command: {command.read_text().strip()}")
        stderr = self.workdir / "stderr.txt"
        tail = stderr.read_text(errors="replace").splitlines()[-STDERR_LINES:] if stderr.exists() else []
        if tail:
            lines.append(f"  stderr (last {len(tail)} lines):")
            lines += [f"    {line}" for line in tail]
        return "\n".join(lines)


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("rotorpilot", "rotorpilot autopilot fixtures (rotorpilot-gcs)")
    group.addoption("--rotorpilot-bin", metavar="PATH", default=None,
                    help="the rotorpilot binary (else $ROTORPILOT_BIN, else the package's own, else rotorpilot "
                         "on PATH)")
    group.addoption("--rotorpilot-keep", action="store_true", default=False,
                    help="keep every autopilot's run directory, not only those of failed tests")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", f"{MARKER}(**options): options of the autopilot fixture's `rotorpilot run` (airframe, "
        "controller, speedup, params, log, log_profile, count, sensors, args, env, duration, timeout)")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Iterator[None]:
    """A failed setup or test keeps its autopilots' run directories and names them in its report."""
    outcome = yield
    report = outcome.get_result()  # type: ignore[attr-defined]
    runs = item.stash.get(_RUNS, [])
    if not report.failed or not runs or report.when == "teardown":
        return
    item.stash[_FAILED] = True
    text = "\n".join(run.describe() for run in runs)
    if hasattr(report.longrepr, "addsection"):
        report.longrepr.addsection("rotorpilot run kept", text)
    else:
        report.sections.append(("rotorpilot run kept", text))


@pytest.fixture(scope="session")
def rotorpilot_bin(pytestconfig: pytest.Config) -> Path:
    """The rotorpilot binary under test."""
    try:
        return find_binary(pytestconfig.getoption("rotorpilot_bin"))
    except FileNotFoundError as e:
        pytest.fail(str(e), pytrace=False)


@pytest.fixture(scope="session")
def rotorpilot(rotorpilot_bin: Path,
               tmp_path_factory: pytest.TempPathFactory) -> Callable[..., subprocess.CompletedProcess[str]]:
    """``rotorpilot(*args, timeout=120)`` runs the binary with `args`; the CompletedProcess (text).
    Its per-user state directory (where ``run`` keeps its flight logs) is a temporary one."""
    env = {**os.environ, "XDG_STATE_HOME": str(tmp_path_factory.mktemp("rotorpilot-state"))}

    def run(*args: Any, timeout: float = 120.0) -> subprocess.CompletedProcess[str]:
        return subprocess.run([str(rotorpilot_bin), *map(str, args)], capture_output=True, text=True,
                              timeout=timeout, check=False, env=env)

    return run


def _dirname(name: str) -> str:
    return "rotorpilot-" + re.sub(r"\W", "_", name)[:40]


@pytest.fixture
def autopilot_factory(request: pytest.FixtureRequest, rotorpilot_bin: Path,
                      tmp_path_factory: pytest.TempPathFactory) -> Iterator[Callable[..., Autopilot]]:
    """``autopilot_factory(**options)``: starts ``rotorpilot run`` with the options of
    `Autopilot.start` over those of the test's ``@pytest.mark.rotorpilot(...)`` markers; stopped
    after the test, run directory kept if the test fails."""
    runs: list[_Run] = request.node.stash.setdefault(_RUNS, [])
    defaults = _marker_options(request)

    def start(**options: Any) -> Autopilot:
        if "workdir" in options or "binary" in options:
            raise TypeError("the fixture chooses workdir and binary (see --rotorpilot-bin)")
        run = _Run(tmp_path_factory.mktemp(_dirname(request.node.name)))
        runs.append(run)
        merged = {**defaults, **options}
        merged["env"] = {"XDG_STATE_HOME": str(run.workdir / "state"), **(merged.get("env") or {})}
        run.autopilot = Autopilot.start(rotorpilot_bin, workdir=run.workdir, **merged)
        return run.autopilot

    yield start
    for run in runs:
        if run.autopilot is not None:
            run.autopilot.stop()
    if not (request.node.stash.get(_FAILED, False) or request.config.getoption("rotorpilot_keep")):
        for run in runs:
            shutil.rmtree(run.workdir, ignore_errors=True)


@pytest.fixture
def autopilot(request: pytest.FixtureRequest, autopilot_factory: Callable[..., Autopilot]) -> Autopilot:
    """A started, connected ``rotorpilot run`` for this test, with the options of its
    ``@pytest.mark.rotorpilot(...)`` marker, ready to arm (its navigation filter aligned and on
    GPS: SYS_STATUS's pre-arm check) unless ``connect=False``."""
    ap = autopilot_factory()
    if _marker_options(request).get("connect", True):
        ap.vehicle.wait_armable()
    return ap


@pytest.fixture
def vehicle(autopilot: Autopilot) -> Vehicle:
    """The `Vehicle` of the ``autopilot`` fixture (its GCS link, ready to arm): for a test that
    only flies (``vehicle.takeoff(3.0)``)."""
    return autopilot.vehicle


def _marker_options(request: pytest.FixtureRequest) -> dict[str, Any]:
    """The options of the test's ``@pytest.mark.rotorpilot(...)`` markers (test, class, module;
    the closest wins per option)."""
    options: dict[str, Any] = {}
    for marker in reversed(list(request.node.iter_markers(MARKER))):
        if marker.args:
            raise TypeError(f"@pytest.mark.{MARKER} takes keyword options only, not {marker.args!r}")
        options.update(marker.kwargs)
    return options
