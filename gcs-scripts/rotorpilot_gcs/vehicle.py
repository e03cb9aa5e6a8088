"""`Vehicle`: the helpers as methods of one connected autopilot (each method is the module
function of the same name with this vehicle's connection)."""
from __future__ import annotations

from typing import Any, Callable, Iterable

from . import commands, flight, link, missions, offboard, params, telemetry
from .link import Connection, Message, Types
from .missions import MISSION, MissionItem
from .modes import Mode


class Vehicle:
    """One autopilot reached over a pymavlink connection `conn` (see `link.connect`)."""

    def __init__(self, conn: Connection) -> None:
        self._conn = conn

    def __repr__(self) -> str:
        return f"Vehicle(system={self._conn.target_system}, connection={getattr(self._conn, 'address', '?')!r})"

    @classmethod
    def connect(cls, connection: str = link.DEFAULT_CONNECTION, timeout: float = link.DEFAULT_TIMEOUT) -> Vehicle:
        """Opens `connection` and waits for the autopilot's heartbeat (`link.connect`)."""
        return cls(link.connect(connection, timeout))

    @property
    def conn(self) -> Connection:
        """The pymavlink connection (``.mav.*_send`` to send anything, ``.recv_match`` to read raw)."""
        return self._conn

    def close(self) -> None:
        """Closes the connection."""
        link.forget(self._conn)
        self._conn.close()

    # The link.
    def recv(self, timeout: float) -> Message | None:
        """`link.recv`: the next message within `timeout` [s], or None."""
        return link.recv(self.conn, timeout)

    def wait(self, types: Types, predicate: Callable[[Message], Any] | None = None, timeout: float | None = None,
             what: str | None = None) -> Message:
        """`link.wait`: the first message of `types` satisfying `predicate`, else `LinkTimeout`."""
        return link.wait(self.conn, types, predicate, timeout, what)

    def sleep(self, seconds: float, on_message: Callable[[Message], Any] | None = None) -> None:
        """`link.sleep`: keeps the link serviced for `seconds`."""
        link.sleep(self.conn, seconds, on_message)

    def set_heartbeats(self, enabled: bool) -> None:
        """`link.set_heartbeats`: the GCS heartbeat on or off."""
        link.set_heartbeats(self.conn, enabled)

    # Commands.
    def command(self, cmd_id: int, *params: float | None, timeout: float | None = None) -> Message:
        """`commands.command`: COMMAND_LONG, retried; the ACK, `CommandError` unless ACCEPTED."""
        return commands.command(self.conn, cmd_id, *params, timeout=timeout)

    def command_ack(self, cmd_id: int, *params: float | None, timeout: float = commands.ACK_TIMEOUT_S,
                    target: tuple[int, int] | None = None) -> Message | None:
        """`commands.command_ack`: one COMMAND_LONG; its COMMAND_ACK (any result) or None."""
        return commands.command_ack(self.conn, cmd_id, *params, timeout=timeout, target=target)

    def request_message(self, msg_id: int, kind: str, timeout: float | None = None) -> Message:
        """`commands.request_message`: the `kind` message answering REQUEST_MESSAGE `msg_id`."""
        return commands.request_message(self.conn, msg_id, kind, timeout)

    # Flying.
    def set_mode(self, mode: Mode, timeout: float | None = None) -> Message:
        """`flight.set_mode`: DO_SET_MODE; the HEARTBEAT showing `mode`."""
        return flight.set_mode(self.conn, mode, timeout=timeout)

    def wait_armable(self, timeout: float | None = None) -> Message:
        """`telemetry.wait_armable`: the first SYS_STATUS saying the vehicle is ready to arm."""
        return telemetry.wait_armable(self.conn, timeout)

    def arm(self, timeout: float | None = None, *, force: bool = False) -> Message:
        """`flight.arm`; the armed HEARTBEAT."""
        return flight.arm(self.conn, timeout, force=force)

    def disarm(self, timeout: float | None = None, *, force: bool = False) -> Message:
        """`flight.disarm`; the disarmed HEARTBEAT."""
        return flight.disarm(self.conn, timeout, force=force)

    def takeoff(self, height: float | None = None, timeout: float | None = None,
                climb_timeout: float | None = None) -> float:
        """`flight.takeoff`: NAV_TAKEOFF, arm, wait for IN_AIR; the height [m]."""
        return flight.takeoff(self.conn, height, timeout, climb_timeout)

    def land(self, timeout: float | None = None) -> Message:
        """`flight.land`: NAV_LAND (ACCEPTED)."""
        return flight.land(self.conn, timeout)

    def return_to_launch(self, timeout: float | None = None) -> Message:
        """`flight.return_to_launch`: NAV_RETURN_TO_LAUNCH (ACCEPTED)."""
        return flight.return_to_launch(self.conn, timeout)

    # Telemetry.
    def wait_heartbeat(self, predicate: Callable[[Message], Any] | None = None,
                       timeout: float | None = None) -> Message:
        """`telemetry.wait_heartbeat`: the autopilot's first HEARTBEAT satisfying `predicate`."""
        return telemetry.wait_heartbeat(self.conn, predicate, timeout)

    def wait_armed(self, timeout: float | None = None) -> Message:
        """`telemetry.wait_armed`."""
        return telemetry.wait_armed(self.conn, timeout)

    def wait_disarmed(self, timeout: float | None = None) -> Message:
        """`telemetry.wait_disarmed`."""
        return telemetry.wait_disarmed(self.conn, timeout)

    def wait_mode(self, mode: Mode, timeout: float | None = None) -> Message:
        """`telemetry.wait_mode`: the first HEARTBEAT in `mode`."""
        return telemetry.wait_mode(self.conn, mode, timeout)

    def wait_in_air(self, timeout: float | None = None) -> Message:
        """`telemetry.wait_in_air`."""
        return telemetry.wait_in_air(self.conn, timeout)

    def wait_on_ground(self, timeout: float | None = None) -> Message:
        """`telemetry.wait_on_ground`."""
        return telemetry.wait_on_ground(self.conn, timeout)

    def home_position(self, timeout: float | None = None) -> tuple[float, float, float]:
        """`telemetry.home_position`: (lat [deg], lon [deg], alt [m AMSL])."""
        return telemetry.home_position(self.conn, timeout)

    def local_position(self, timeout: float | None = None) -> Message:
        """`telemetry.local_position`: a fresh LOCAL_POSITION_NED."""
        return telemetry.local_position(self.conn, timeout)

    # Parameters.
    def param_get(self, name: str, timeout: float | None = None) -> float | int:
        """`params.param_get`."""
        return params.param_get(self.conn, name, timeout)

    def param_set(self, name: str, value: float, int32: bool | None = None,
                  timeout: float | None = None) -> float | int:
        """`params.param_set`: set and check the echo; the echoed value."""
        return params.param_set(self.conn, name, value, int32, timeout)

    def param_list(self, timeout: float | None = None) -> dict[str, float | int]:
        """`params.param_list`: every parameter by name, missing ones re-requested."""
        return params.param_list(self.conn, timeout)

    # Plans.
    def upload_mission(self, items: Iterable[MissionItem], mission_type: int = MISSION,
                       timeout: float | None = None) -> Message:
        """`missions.upload_mission`; the MISSION_ACK, `MissionError` unless ACCEPTED."""
        return missions.upload_mission(self.conn, items, mission_type, timeout)

    def download_mission(self, mission_type: int = MISSION, timeout: float | None = None) -> list[MissionItem]:
        """`missions.download_mission`."""
        return missions.download_mission(self.conn, mission_type, timeout)

    def clear_mission(self, mission_type: int = MISSION, timeout: float | None = None) -> Message:
        """`missions.clear_mission`."""
        return missions.clear_mission(self.conn, mission_type, timeout)

    # Offboard.
    def set_setpoint(self, x: float, y: float, z: float, yaw: float = 0.0) -> None:
        """`offboard.set_setpoint`: stream a LOCAL_NED position setpoint at 20 Hz."""
        offboard.set_setpoint(self.conn, x, y, z, yaw)

    def stop_setpoints(self) -> None:
        """`offboard.stop_setpoints`."""
        offboard.stop_setpoints(self.conn)
