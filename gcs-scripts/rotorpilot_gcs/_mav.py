"""pymavlink, loaded for MAVLink 2.

pymavlink picks its wire protocol when it is first imported (the ``MAVLINK20`` environment
variable); this module sets it first and, if pymavlink was already loaded for MAVLink 1, loads
the dialect again for MAVLink 2.
"""
import os
from typing import Any

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

if mavutil.mavlink.WIRE_PROTOCOL_VERSION != "2.0":
    mavutil.set_dialect(mavutil.current_dialect)

#: The generated MAVLink 2 dialect module (message classes, enums and ``MAV_*`` constants).
mavlink = mavutil.mavlink


def connection_with_dialect(device: str, dialect: str, **options: Any) -> Any:
    """``mavutil.mavlink_connection(device, dialect=dialect, **options)`` without changing the
    dialect of the links made after it: pymavlink's dialect is process-wide, and the link keeps
    the parser it was built with, so the previous dialect is put back at once (a link with
    QGroundControl's ``common`` would otherwise leave every later link unable to read another
    dialect's messages, ArduPilot's EKF_STATUS_REPORT for one)."""
    previous = mavutil.current_dialect
    try:
        return mavutil.mavlink_connection(device, dialect=dialect, **options)
    finally:
        mavutil.set_dialect(previous)


__all__ = ["connection_with_dialect", "mavlink", "mavutil"]
