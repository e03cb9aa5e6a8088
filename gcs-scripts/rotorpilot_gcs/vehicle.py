"""`Vehicle`: one autopilot over one pymavlink connection, the link and the helpers' state of it.

The library's calls are module functions taking the connection (``takeoff(conn, 3.0)``); a
`Vehicle` has them as methods bound to its connection (``vehicle.takeoff(3.0)``): each method is
the function itself with the connection filled in, documented once, in its module.
"""
from __future__ import annotations

import functools
from typing import Any, Callable, Concatenate, Generic, ParamSpec, TypeVar, cast, overload

from . import commands, flight, link, missions, offboard, params, telemetry
from .link import Connection, LinkState

P = ParamSpec("P")
R = TypeVar("R")


class _Bound(Generic[P, R]):
    """A module function as a method of `Vehicle`: ``vehicle.f(*args)`` is ``f(vehicle.conn, *args)``."""

    def __init__(self, function: Callable[Concatenate[Connection, P], R]) -> None:
        self.function = function
        self.__doc__ = function.__doc__

    @overload
    def __get__(self, vehicle: None, owner: type[Any]) -> _Bound[P, R]: ...

    @overload
    def __get__(self, vehicle: Vehicle, owner: type[Any]) -> Callable[P, R]: ...

    def __get__(self, vehicle: Vehicle | None, owner: type[Any]) -> _Bound[P, R] | Callable[P, R]:
        if vehicle is None:
            return self
        return cast(Callable[P, R], functools.partial(self.function, vehicle.conn))


class Vehicle:
    """One autopilot reached over the pymavlink connection `conn` (see `link.connect`), and the
    helpers' state of that link (`state`). `Vehicle.connect` opens one; `Autopilot.vehicle` is
    the one of a started ``rotorpilot run``."""

    def __init__(self, conn: Connection) -> None:
        self._conn = conn
        self._state = link.link_state(conn)

    def __repr__(self) -> str:
        return f"Vehicle(system={self._conn.target_system}, connection={getattr(self._conn, 'address', '?')!r})"

    @classmethod
    def connect(cls, connection: str | Connection = link.DEFAULT_CONNECTION, timeout: float = link.DEFAULT_TIMEOUT,
                **options: Any) -> Vehicle:
        """Opens `connection` and waits for the autopilot's heartbeat (`link.connect`, same options)."""
        return cls(link.connect(connection, timeout, **options))

    @property
    def conn(self) -> Connection:
        """The pymavlink connection (``.mav.*_send`` to send anything, ``.recv_match`` to read raw)."""
        return self._conn

    @property
    def state(self) -> LinkState:
        """The helpers' state of the link (time-out, periodic sends, latest messages, texts...)."""
        return self._state

    @property
    def personality(self) -> str:
        """``"px4"`` or ``"ardupilot"``, from the HEARTBEAT's autopilot field (`link.personality`):
        the mode names and the ways of the helpers this vehicle is flown with."""
        return link.personality(self._conn)

    @property
    def sysid(self) -> int:
        """The autopilot's MAVLink system id."""
        return int(self._conn.target_system)

    def close(self) -> None:
        """Stops servicing the link (`link.forget`) and closes the connection."""
        link.forget(self._conn)
        self._conn.close()

    def __enter__(self) -> Vehicle:
        return self

    def __exit__(self, kind: object, value: object, traceback: object) -> None:
        self.close()

    # The link.
    recv = _Bound(link.recv)
    wait = _Bound(link.wait)
    sleep = _Bound(link.sleep)
    latest = _Bound(link.latest)
    recent_text = _Bound(link.recent_text)
    send_heartbeat = _Bound(link.send_heartbeat)
    set_heartbeats = _Bound(link.set_heartbeats)
    set_periodic = _Bound(link.set_periodic)
    request_streams = _Bound(link.request_streams)
    stop_periodic = _Bound(link.stop_periodic)
    # Commands.
    command = _Bound(commands.command)
    command_ack = _Bound(commands.command_ack)
    request_message = _Bound(commands.request_message)
    # Flying.
    set_mode = _Bound(flight.set_mode)
    arm = _Bound(flight.arm)
    disarm = _Bound(flight.disarm)
    takeoff = _Bound(flight.takeoff)
    land = _Bound(flight.land)
    return_to_launch = _Bound(flight.return_to_launch)
    # Telemetry.
    wait_heartbeat = _Bound(telemetry.wait_heartbeat)
    wait_armable = _Bound(telemetry.wait_armable)
    wait_armed = _Bound(telemetry.wait_armed)
    wait_disarmed = _Bound(telemetry.wait_disarmed)
    wait_mode = _Bound(telemetry.wait_mode)
    current_mode = _Bound(telemetry.current_mode)
    wait_landed_state = _Bound(telemetry.wait_landed_state)
    wait_in_air = _Bound(telemetry.wait_in_air)
    wait_on_ground = _Bound(telemetry.wait_on_ground)
    home_position = _Bound(telemetry.home_position)
    local_position = _Bound(telemetry.local_position)
    relative_altitude = _Bound(telemetry.relative_altitude)
    wait_height = _Bound(telemetry.wait_height)
    # Parameters.
    param_get = _Bound(params.param_get)
    param_set = _Bound(params.param_set)
    param_list = _Bound(params.param_list)
    # Plans.
    upload_mission = _Bound(missions.upload_mission)
    download_mission = _Bound(missions.download_mission)
    clear_mission = _Bound(missions.clear_mission)
    wait_item_reached = _Bound(missions.wait_item_reached)
    # Offboard.
    set_setpoint = _Bound(offboard.set_setpoint)
    stop_setpoints = _Bound(offboard.stop_setpoints)
