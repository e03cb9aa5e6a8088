"""Flying: modes, arming, take-off and landing, each confirmed by the autopilot.

The same calls fly both personalities (`link.personality`), each as its own ground stations fly
it: on PX4 the commands QGroundControl sends (NAV_TAKEOFF to an AMSL altitude in AUTO.TAKEOFF,
NAV_LAND, NAV_RETURN_TO_LAUNCH); on ArduCopter what Copter users do (GUIDED, arm, NAV_TAKEOFF to
a height above home; the LAND and RTL modes). Mode names are the personality's (`modes`).
"""
from __future__ import annotations

from . import modes
from ._mav import mavlink
from .commands import NAN, command
from .link import Connection, Message, personality
from .modes import ARDUPILOT, COPTER_MODES, Mode, vehicle_custom_mode
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
    wait_height,
    wait_landed_state,
    wait_mode,
)

#: COMPONENT_ARM_DISARM param2 that forces the change (PX4: arming checks skipped, disarm in the air).
FORCE = 21196


def set_mode(conn: Connection, mode: Mode | int, sub: int | None = None, timeout: float | None = None) -> Message:
    """DO_SET_MODE to `mode` with the custom-mode flag; returns the HEARTBEAT that shows it. PX4:
    ``"OFFBOARD"``, (main, sub), or main mode and `sub` as ints; ArduCopter: a Copter name
    (``"GUIDED"``) or number. `ModeError` (naming the mode and the personality) for a name of the
    other personality: no name is mapped."""
    face = personality(conn)
    value = vehicle_custom_mode(face, mode, sub)
    if face == ARDUPILOT:
        command(conn, mavlink.MAV_CMD_DO_SET_MODE, mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, value, 0,
                timeout=timeout)
        return wait_mode(conn, value, timeout)
    main, sub_mode = (value >> 16) & 0xFF, (value >> 24) & 0xFF
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
    """Once the vehicle is ready to arm (`wait_armable`), take off to `height` [m] above home
    (None: the autopilot's MIS_TAKEOFF_ALT) and wait until the take-off is complete (within
    `climb_timeout` [s], default 15 s + 2 s per metre): `start_takeoff`, then `wait_takeoff`.
    Returns the height."""
    height = start_takeoff(conn, height, timeout)
    wait_takeoff(conn, height, climb_timeout)
    return height


def start_takeoff(conn: Connection, height: float | None = None, timeout: float | None = None) -> float:
    """The commands of a take-off to `height` [m] above home (None: MIS_TAKEOFF_ALT), once the
    vehicle is ready to arm, without waiting for the climb (a swarm takes off together); returns
    the height.

    PX4: NAV_TAKEOFF (p7 AMSL: home altitude + height), arm if disarmed. ArduCopter (Copter's user
    take-off): GUIDED, arm if disarmed, NAV_TAKEOFF with p7 the height above home; the vehicle
    then holds there in GUIDED (armed without a take-off, Copter disarms after DISARM_DELAY: the
    take-off follows the arming at once)."""
    wait_armable(conn, max(READY_TIMEOUT_S, timeout or 0.0))
    asked = height
    height = float(param_get(conn, "MIS_TAKEOFF_ALT", timeout) if asked is None else asked)
    if personality(conn) == ARDUPILOT:
        _armed_in_guided(conn, timeout)
        command(conn, mavlink.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, height, timeout=timeout)
        return height
    # p7 NaN: the autopilot's MIS_TAKEOFF_ALT.
    p7 = NAN if asked is None else home_position(conn, timeout)[2] + height
    command(conn, mavlink.MAV_CMD_NAV_TAKEOFF, *([NAN] * 6), p7, timeout=timeout)
    if not is_armed(wait_heartbeat(conn, None, timeout)):
        arm(conn, timeout=timeout)
    return height


def _armed_in_guided(conn: Connection, timeout: float | None) -> Message:
    """An ArduCopter vehicle in GUIDED and armed, where Copter users take off and start missions
    from (each step only if needed); returns the HEARTBEAT that shows it."""
    hb = wait_heartbeat(conn, None, timeout)
    if hb.custom_mode != COPTER_MODES["GUIDED"]:
        hb = set_mode(conn, "GUIDED", timeout=timeout)
    if not is_armed(hb):
        hb = arm(conn, timeout=timeout)
    return hb


def wait_takeoff(conn: Connection, height: float, climb_timeout: float | None = None) -> None:
    """Waits until the take-off `start_takeoff` began to `height` [m] is complete (within
    `climb_timeout` [s], default 15 s + 2 s per metre). PX4: the landed state IN_AIR; ArduCopter:
    GLOBAL_POSITION_INT near the height (`wait_height`)."""
    climb = climb_timeout if climb_timeout is not None else 15.0 + 2.0 * float(height)
    if personality(conn) == ARDUPILOT:
        wait_height(conn, float(height), climb)
    else:
        wait_landed_state(conn, IN_AIR, climb)


def mode_for(conn: Connection, role: str) -> str:
    """The name of the mode the vehicle on `conn` does `role` in (`modes.SETPOINTS`: PX4's
    OFFBOARD, Copter's GUIDED; `modes.HOLD`; `modes.MISSION`), for `set_mode`."""
    return modes.mode_for(personality(conn), role)


def start_mission(conn: Connection, timeout: float | None = None) -> Message:
    """Starts the uploaded mission from the ground, once the vehicle is ready to arm; returns the
    armed HEARTBEAT in the mission mode. PX4: AUTO.MISSION, then arm (the mission's take-off
    item takes off). ArduCopter: GUIDED, arm, AUTO, as Copter users do (Copter takes AUTO on the
    ground only when the mission begins with a take-off: otherwise `CommandError`)."""
    wait_armable(conn, max(READY_TIMEOUT_S, timeout or 0.0))
    if personality(conn) == ARDUPILOT:
        _armed_in_guided(conn, timeout)
        return set_mode(conn, "AUTO", timeout=timeout)
    set_mode(conn, modes.AUTO_MISSION, timeout=timeout)
    return arm(conn, timeout=timeout)


def land(conn: Connection, timeout: float | None = None) -> Message:
    """Lands where the vehicle is; then `wait_on_ground` / `wait_disarmed`. PX4: NAV_LAND, its
    COMMAND_ACK (ACCEPTED); ArduCopter: the LAND mode, the HEARTBEAT that shows it."""
    if personality(conn) == ARDUPILOT:
        return set_mode(conn, "LAND", timeout=timeout)
    return command(conn, mavlink.MAV_CMD_NAV_LAND, timeout=timeout)


def return_to_launch(conn: Connection, timeout: float | None = None) -> Message:
    """Returns home and lands. PX4: NAV_RETURN_TO_LAUNCH, its COMMAND_ACK (ACCEPTED);
    ArduCopter: the RTL mode, the HEARTBEAT that shows it."""
    if personality(conn) == ARDUPILOT:
        return set_mode(conn, "RTL", timeout=timeout)
    return command(conn, mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, timeout=timeout)

