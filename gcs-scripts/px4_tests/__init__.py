"""PX4's MAVSDK integration suite for multicopters, ported to MAVSDK-Python, flown against rotorpilot.

The facts (the steps of each case, tolerances, time-outs, parameters, waypoints) come from
PX4-Autopilot's `test/mavsdk_tests/` (autopilot_tester*.cpp/.h, test_multicopter_*.cpp,
test_param_ftp.cpp, test_sih_basic.cpp, mavsdk_test_runner.py, configs/*.json); the Python is
written afresh. Each module `test_*.py` here stands for the PX4 file of that name and holds one
async function per TEST_CASE, registered with `case` under PX4's case name;
`gcs-scripts/run_px4_tests.py` runs them.

Where PX4's newest text compiles a case out (`#if 0`), that text is kept, flagged
`disabled_upstream`, and runs like the others. Two defaults are missing from the stored copy of
PX4's header and are taken as 0.1 m (`wait_until_altitude`'s band) and 5 s (`get_home_position`).

Left out, as they cannot apply to a multicopter on rotorpilot: the VTOL, fixed-wing and tailsitter
cases (test_vtol_*, test_fw_mission, test_mission_plane/vtol, test_sih_xvert_transition,
test_sih_catapult_launch); optical flow (test_multicopter_optical_flow: a flow sensor and no GPS);
terrain (test_multicopter_terrain: SIH's hilly ground and a rangefinder); GNSS failover (two GPS
receivers); EKF failover and the estimator selector (test_multicopter_ekf_failover,
test_ekf2_selector: two estimator instances switched by SIH's per-IMU fault parameters and read
through the nsh shell). test_mission_multicopter.cpp holds no case; test_mavlink_param_validation.py
is a pymavlink script outside the MAVSDK runner. The SIH home-yaw case is listed but reported
"not applicable" (see test_multicopter_home.py).
"""
from __future__ import annotations

import dataclasses
import importlib
from typing import Awaitable, Callable

#: The modules holding cases, in PX4's order of files.
MODULES = (
    "test_multicopter_mission", "test_multicopter_basics", "test_multicopter_offboard",
    "test_multicopter_manual", "test_multicopter_failsafe", "test_multicopter_failure_injection",
    "test_multicopter_follow_me", "test_multicopter_goto", "test_multicopter_home", "test_multicopter_rtl",
    "test_multicopter_rtl_with_geofence", "test_multicopter_missed_waypoint", "test_multicopter_mission_do_jump",
    "test_multicopter_control_allocation", "test_param_ftp", "test_sih_basic", "test_multicopter_sih_gravity",
)

#: The PX4 connection every case uses (PX4 SITL sends its API link to 14540).
CONNECTION_URL = "udpin://0.0.0.0:14540"


@dataclasses.dataclass(frozen=True)
class Case:
    """One TEST_CASE: PX4's name and tags, the coroutine, and what PX4's runner config gives it."""
    name: str
    tags: str
    run: Callable[[str], Awaitable[None]]
    module: str
    #: rotorpilot airframe standing for the config's model (iris → quad_x, the hexarotors → hexa_x).
    airframe: str = "quad_x"
    #: Parameters the config sets at boot (PX4_PARAM_* in the test's "env").
    boot_params: tuple[tuple[str, float], ...] = ()
    #: Why the case cannot apply to rotorpilot at all (then it is reported, not run).
    not_applicable: str | None = None
    #: True when PX4 compiles the case out (#if 0) in its newest text.
    disabled_upstream: bool = False


_REGISTRY: dict[str, Case] = {}


def case(name: str, tags: str, **options) -> Callable:
    """Registers the decorated coroutine (taking the connection URL) as the PX4 case `name`."""
    def register(fn):
        _REGISTRY[name] = Case(name=name, tags=tags, run=fn, module=fn.__module__.rsplit(".", 1)[-1], **options)
        return fn
    return register


def all_cases() -> list[Case]:
    """Every registered case, module by module in `MODULES` order."""
    for module in MODULES:
        importlib.import_module(f"{__name__}.{module}")
    order = {m: i for i, m in enumerate(MODULES)}
    return sorted(_REGISTRY.values(), key=lambda c: order[c.module])
