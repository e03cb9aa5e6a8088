"""Waiting on the autopilot's telemetry: heartbeat (armed, mode), landed state, positions."""
from __future__ import annotations

from typing import Any, Callable

from ._mav import mavlink
from .commands import request_message
from .link import Connection, Message, wait
from .modes import Mode, custom_mode, mode_name
from .names import enum_name

#: MAV_LANDED_STATE values (EXTENDED_SYS_STATE.landed_state).
ON_GROUND, IN_AIR, TAKEOFF, LANDING = 1, 2, 3, 4


def is_armed(hb: Message) -> bool:
    """Whether a HEARTBEAT says the vehicle is armed."""
    return bool(hb.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED)


def wait_heartbeat(conn: Connection, predicate: Callable[[Message], Any] | None = None,
                   timeout: float | None = None, what: str = "heartbeat") -> Message:
    """The first HEARTBEAT of the target autopilot (its component) satisfying `predicate`."""
    return wait(conn, "HEARTBEAT", lambda m: m.get_srcComponent() == conn.target_component
                and (predicate is None or predicate(m)), timeout, what)


#: How long a vehicle may take to be ready to arm after start [s]: the navigation filter aligns
#: at rest (1 s of simulated time) and takes the first GPS fixes; slow speed-ups stretch it.
READY_TIMEOUT_S = 30.0


def is_armable(sys_status: Message) -> bool:
    """Whether a SYS_STATUS says arming would pass the checks (the pre-arm bit healthy, MAVSDK's
    `is_armable`)."""
    bit = mavlink.MAV_SYS_STATUS_PREARM_CHECK
    return bool(sys_status.onboard_control_sensors_present & bit
                and sys_status.onboard_control_sensors_health & bit)


def wait_armable(conn: Connection, timeout: float | None = None) -> Message:
    """The first SYS_STATUS saying the vehicle is ready to arm: its navigation estimate is
    aligned and has a position (PX4's pre-arm checks; QGroundControl shows "Ready To Fly")."""
    return wait(conn, "SYS_STATUS", is_armable, READY_TIMEOUT_S if timeout is None else timeout,
                "ready to arm (SYS_STATUS pre-arm check)")


def wait_armed(conn: Connection, timeout: float | None = None) -> Message:
    """The first armed HEARTBEAT."""
    return wait_heartbeat(conn, is_armed, timeout, "an armed heartbeat")


def wait_disarmed(conn: Connection, timeout: float | None = None) -> Message:
    """The first disarmed HEARTBEAT (after a landing: the autopilot's auto-disarm)."""
    return wait_heartbeat(conn, lambda m: not is_armed(m), timeout, "a disarmed heartbeat")


def wait_mode(conn: Connection, mode: Mode, timeout: float | None = None) -> Message:
    """The first HEARTBEAT showing `mode` (``"AUTO.RTL"`` or (main, sub))."""
    wanted = custom_mode(mode)
    return wait_heartbeat(conn, lambda m: m.custom_mode == wanted, timeout, f"heartbeat in {mode_name(wanted)}")


def wait_landed_state(conn: Connection, state: int, timeout: float | None = None) -> Message:
    """The first EXTENDED_SYS_STATE with landed_state `state` (`ON_GROUND`, `IN_AIR`, ...)."""
    name = enum_name("MAV_LANDED_STATE", state)
    return wait(conn, "EXTENDED_SYS_STATE", lambda m: m.landed_state == state, timeout, f"landed state {name}")


def wait_in_air(conn: Connection, timeout: float | None = None) -> Message:
    """The first EXTENDED_SYS_STATE saying IN_AIR (a take-off is complete)."""
    return wait_landed_state(conn, IN_AIR, timeout)


def wait_on_ground(conn: Connection, timeout: float | None = None) -> Message:
    """The first EXTENDED_SYS_STATE saying ON_GROUND (landed)."""
    return wait_landed_state(conn, ON_GROUND, timeout)


def home_position(conn: Connection, timeout: float | None = None) -> tuple[float, float, float]:
    """Home as (latitude [deg], longitude [deg], altitude [m AMSL]), asked for by REQUEST_MESSAGE."""
    m = request_message(conn, mavlink.MAVLINK_MSG_ID_HOME_POSITION, "HOME_POSITION", timeout)
    return m.latitude * 1e-7, m.longitude * 1e-7, m.altitude * 1e-3


def local_position(conn: Connection, timeout: float | None = None) -> Message:
    """A fresh LOCAL_POSITION_NED (x north, y east, z down from home [m]; it streams at 1 Hz
    only, so it is asked for)."""
    return request_message(conn, mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED, "LOCAL_POSITION_NED", timeout)


def format_position(m: Message) -> str:
    """``north +0.00 m, east +0.00 m, up +2.50 m`` of a LOCAL_POSITION_NED."""
    return f"north {m.x:+.2f} m, east {m.y:+.2f} m, up {-m.z:+.2f} m"
