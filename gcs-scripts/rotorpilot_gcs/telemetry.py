"""Waiting on the autopilot's telemetry: heartbeat (armed, mode), landed state, positions.

Each wait reads the telemetry the vehicle's personality sends (`link.personality`): PX4's
SYS_STATUS pre-arm bit and EXTENDED_SYS_STATE; ArduCopter's SYS_STATUS pre-arm bit (else its
EKF_STATUS_REPORT and GPS fix, as DroneKit's ``is_armable``) and its HEARTBEAT's system status
for the landed state (STANDBY on the ground, ACTIVE in the air), its modes by Copter's names."""
from __future__ import annotations

from typing import Any, Callable

from ._mav import mavlink
from .commands import request_message
from .errors import GcsError
from .link import Connection, Message, personality, wait
from .modes import ARDUPILOT, Mode, vehicle_custom_mode, vehicle_mode_name
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


#: EKF_STATUS_REPORT.flags bit of a predicted absolute horizontal position (EKF_PRED_POS_HORIZ_ABS),
#: which DroneKit's ``is_armable`` reads.
EKF_PRED_POS_HORIZ_ABS = 512


class _CopterReadiness:
    """ArduCopter's readiness from its streams: the SYS_STATUS pre-arm bit when the vehicle
    reports it; else, as DroneKit judges it, EKF_STATUS_REPORT's predicted absolute horizontal
    position and a GPS fix (GPS_RAW_INT fix_type > 1)."""

    def __init__(self) -> None:
        self.prearm_reported = False
        self.ekf_ok = self.gps_ok = False

    def __call__(self, m: Message) -> bool:
        kind = m.get_type()
        if kind == "SYS_STATUS":
            if m.onboard_control_sensors_present & mavlink.MAV_SYS_STATUS_PREARM_CHECK:
                self.prearm_reported = True
                return is_armable(m)
        elif kind == "EKF_STATUS_REPORT":
            self.ekf_ok = bool(m.flags & EKF_PRED_POS_HORIZ_ABS)
        elif kind == "GPS_RAW_INT":
            self.gps_ok = m.fix_type > 1
        return not self.prearm_reported and self.ekf_ok and self.gps_ok


def wait_armable(conn: Connection, timeout: float | None = None) -> Message:
    """The first message saying the vehicle is ready to arm: its navigation estimate is aligned
    and has a position. PX4: SYS_STATUS's pre-arm check (QGroundControl shows "Ready To Fly");
    ArduCopter: the same bit when reported, else EKF_STATUS_REPORT and GPS_RAW_INT (DroneKit's
    ``is_armable``)."""
    timeout = READY_TIMEOUT_S if timeout is None else timeout
    if personality(conn) == ARDUPILOT:
        return wait(conn, ("SYS_STATUS", "EKF_STATUS_REPORT", "GPS_RAW_INT"), _CopterReadiness(), timeout,
                    "ready to arm (SYS_STATUS pre-arm check, or EKF_STATUS_REPORT and a GPS fix)")
    return wait(conn, "SYS_STATUS", is_armable, timeout, "ready to arm (SYS_STATUS pre-arm check)")


def wait_armed(conn: Connection, timeout: float | None = None) -> Message:
    """The first armed HEARTBEAT."""
    return wait_heartbeat(conn, is_armed, timeout, "an armed heartbeat")


def wait_disarmed(conn: Connection, timeout: float | None = None) -> Message:
    """The first disarmed HEARTBEAT (after a landing: the autopilot's auto-disarm)."""
    return wait_heartbeat(conn, lambda m: not is_armed(m), timeout, "a disarmed heartbeat")


def wait_mode(conn: Connection, mode: Mode | int, timeout: float | None = None) -> Message:
    """The first HEARTBEAT showing `mode`: on PX4 ``"AUTO.RTL"`` or (main, sub); on ArduCopter
    ``"RTL"`` or its number (`modes.vehicle_custom_mode`; `ModeError` for the other's names)."""
    face = personality(conn)
    wanted = vehicle_custom_mode(face, mode)
    return wait_heartbeat(conn, lambda m: m.custom_mode == wanted, timeout,
                          f"heartbeat in {vehicle_mode_name(face, wanted)}")


def current_mode(conn: Connection, timeout: float | None = None) -> str:
    """The name of the mode the vehicle's next HEARTBEAT shows, in its personality's names."""
    return vehicle_mode_name(personality(conn), wait_heartbeat(conn, None, timeout).custom_mode)


def _copter_landed(state: int) -> Callable[[Message], bool]:
    """ArduCopter's landed state from its HEARTBEAT (docs/ardupilot.md §2): ACTIVE in the air,
    STANDBY on the ground (armed or not); disarmed counts as on the ground."""
    if state == IN_AIR:
        return lambda m: bool(m.system_status == mavlink.MAV_STATE_ACTIVE)
    if state == ON_GROUND:
        return lambda m: bool(m.system_status == mavlink.MAV_STATE_STANDBY or not is_armed(m))
    raise GcsError(f"ArduCopter reports no landed state {enum_name('MAV_LANDED_STATE', state)} "
                   "(only in the air or on the ground, by its HEARTBEAT)")


def wait_landed_state(conn: Connection, state: int, timeout: float | None = None) -> Message:
    """The first EXTENDED_SYS_STATE with landed_state `state` (`ON_GROUND`, `IN_AIR`, ...); on
    ArduCopter, which reports its landed state in its HEARTBEAT's system status, the first
    HEARTBEAT saying `IN_AIR` (ACTIVE) or `ON_GROUND` (STANDBY, or disarmed); `GcsError` for
    another state."""
    name = enum_name("MAV_LANDED_STATE", state)
    if personality(conn) == ARDUPILOT:
        return wait_heartbeat(conn, _copter_landed(state), timeout, f"landed state {name} (HEARTBEAT)")
    return wait(conn, "EXTENDED_SYS_STATE", lambda m: m.landed_state == state, timeout, f"landed state {name}")


def wait_in_air(conn: Connection, timeout: float | None = None) -> Message:
    """The first EXTENDED_SYS_STATE saying IN_AIR (a take-off is complete)."""
    return wait_landed_state(conn, IN_AIR, timeout)


def wait_on_ground(conn: Connection, timeout: float | None = None) -> Message:
    """The first EXTENDED_SYS_STATE saying ON_GROUND (landed)."""
    return wait_landed_state(conn, ON_GROUND, timeout)


def relative_altitude(conn: Connection, timeout: float | None = None) -> float:
    """The height above home [m] of the next GLOBAL_POSITION_INT (the estimate's)."""
    return float(wait(conn, "GLOBAL_POSITION_INT", None, timeout).relative_alt) / 1000.0


def wait_height(conn: Connection, height: float, timeout: float | None = None, tolerance: float | None = None
                ) -> Message:
    """The first GLOBAL_POSITION_INT at least `height` − `tolerance` [m] above home (default
    tolerance: 5 % of the height, at least 0.25 m), as DroneKit's examples wait for a take-off."""
    tol = max(0.25, 0.05 * abs(height)) if tolerance is None else tolerance
    return wait(conn, "GLOBAL_POSITION_INT", lambda m: m.relative_alt / 1000.0 >= height - tol, timeout,
                f"a height of {height:g} m above home (GLOBAL_POSITION_INT)")


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
