"""Names of MAVLink enum values, for messages and errors."""
from __future__ import annotations

from ._mav import mavlink


def enum_name(enum: str, value: int) -> str:
    """The name of `value` in the MAVLink enum `enum` (``MAV_RESULT_DENIED``), or ``"ENUM value"``
    when the dialect does not know it."""
    entry = mavlink.enums.get(enum, {}).get(value)
    return entry.name if entry is not None else f"{enum} {value}"


def command_name(command: int) -> str:
    """The MAV_CMD name of `command` (``MAV_CMD_NAV_TAKEOFF`` for 22)."""
    return enum_name("MAV_CMD", command)
