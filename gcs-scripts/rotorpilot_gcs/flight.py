"""Flying: modes, arming, take-off and landing, each confirmed by the autopilot."""
from __future__ import annotations

from ._mav import mavlink
from .commands import NAN, command
from .link import Connection, Message
from .modes import Mode, parse_mode
from .params import param_get
from .telemetry import (
    IN_AIR,
    READY_TIMEOUT_S,
    home_position,
    is_armed,
    wait_armable,
    wait_armed,
    wait_disarmed,
    wait_heartbeat,
    wait_landed_state,
    wait_mode,
)

#: COMPONENT_ARM_DISARM param2 that forces the change (PX4: arming checks skipped, disarm in the air).
FORCE = 21196


def set_mode(conn: Connection, mode: Mode | int, sub: int | None = None, timeout: float | None = None) -> Message:
    """DO_SET_MODE to `mode` (``"OFFBOARD"``, (main, sub), or main mode and `sub` as ints) with the
    custom-mode flag; returns the HEARTBEAT that shows it."""
    main, sub_mode = (mode, sub or 0) if isinstance(mode, int) else parse_mode(mode)
    command(conn, mavlink.MAV_CMD_DO_SET_MODE, mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, main, sub_mode,
            timeout=timeout)
    return wait_mode(conn, (main, sub_mode), timeout)


def arm(conn: Connection, timeout: float | None = None, *, force: bool = False) -> Message:
    """COMPONENT_ARM_DISARM 1 once the vehicle is ready to arm (`wait_armable`; `force`: at once,
    the arming checks skipped); returns the armed HEARTBEAT."""
    if not force:
        wait_armable(conn, max(READY_TIMEOUT_S, timeout or 0.0))
    command(conn, mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 1, FORCE if force else 0, timeout=timeout)
    return wait_armed(conn, timeout)


def disarm(conn: Connection, timeout: float | None = None, *, force: bool = False) -> Message:
    """COMPONENT_ARM_DISARM 0 (`force`: also in the air, the motors stop); returns the disarmed
    HEARTBEAT."""
    command(conn, mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 0, FORCE if force else 0, timeout=timeout)
    return wait_disarmed(conn, timeout)


def takeoff(conn: Connection, height: float | None = None, timeout: float | None = None,
            climb_timeout: float | None = None) -> float:
    """Once the vehicle is ready to arm (`wait_armable`), NAV_TAKEOFF to `height` [m] above home
    (None: the autopilot's MIS_TAKEOFF_ALT), arm if
    disarmed, and wait until the take-off is complete (landed state IN_AIR, within
    `climb_timeout` [s], default 15 s + 2 s per metre). p7 is AMSL: home altitude + height.
    Returns the height."""
    wait_armable(conn, max(READY_TIMEOUT_S, timeout or 0.0))
    if height is None:
        p7 = NAN
        height = float(param_get(conn, "MIS_TAKEOFF_ALT", timeout))
    else:
        p7 = home_position(conn, timeout)[2] + float(height)
    command(conn, mavlink.MAV_CMD_NAV_TAKEOFF, *([NAN] * 6), p7, timeout=timeout)
    hb = wait_heartbeat(conn, None, timeout)
    if not is_armed(hb):
        arm(conn, timeout=timeout)
    climb = climb_timeout if climb_timeout is not None else 15.0 + 2.0 * float(height)
    wait_landed_state(conn, IN_AIR, climb)
    return height


def land(conn: Connection, timeout: float | None = None) -> Message:
    """NAV_LAND where the vehicle is (ACCEPTED); then `wait_on_ground` / `wait_disarmed`."""
    return command(conn, mavlink.MAV_CMD_NAV_LAND, timeout=timeout)


def return_to_launch(conn: Connection, timeout: float | None = None) -> Message:
    """NAV_RETURN_TO_LAUNCH (ACCEPTED)."""
    return command(conn, mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, timeout=timeout)

