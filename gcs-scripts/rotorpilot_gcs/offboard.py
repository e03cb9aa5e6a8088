"""Offboard control: a position setpoint streamed at 20 Hz by the link's keeper thread.

PX4 leaves OFFBOARD (and refuses to enter it) when the setpoint stream stops for COM_OF_LOSS_T,
so the stream goes out on its own, whatever the script does meanwhile (sleeps included): start
it before switching to OFFBOARD, move it with further `set_setpoint` calls, stop it after
leaving OFFBOARD.
"""
from __future__ import annotations

import time

from ._mav import mavlink
from .link import Connection, link_state, set_periodic, stop_periodic, weak_sender

#: SET_POSITION_TARGET_LOCAL_NED type_mask: position and yaw only (MAVSDK's set_position_ned).
POSITION_MASK = 2552
#: The setpoint stream's rate [Hz].
SETPOINT_RATE_HZ = 20.0


def set_setpoint(conn: Connection, x: float, y: float, z: float, yaw: float = 0.0) -> None:
    """Streams the LOCAL_NED position setpoint (`x` north, `y` east, `z` down [m], `yaw` [rad])
    at `SETPOINT_RATE_HZ` from now on (replacing the previous one)."""
    started = link_state(conn).started
    target = (float(x), float(y), float(z), float(yaw))

    def send(conn: Connection) -> None:
        boot_ms = int((time.monotonic() - started) * 1000) & 0xFFFFFFFF
        px, py, pz, pyaw = target
        conn.mav.set_position_target_local_ned_send(boot_ms, conn.target_system, conn.target_component,
                                                    mavlink.MAV_FRAME_LOCAL_NED, POSITION_MASK, px, py, pz,
                                                    0, 0, 0, 0, 0, 0, pyaw, 0)

    set_periodic(conn, "setpoint", 1.0 / SETPOINT_RATE_HZ, weak_sender(conn, send))


def stop_setpoints(conn: Connection) -> None:
    """Stops the setpoint stream."""
    stop_periodic(conn, "setpoint")
