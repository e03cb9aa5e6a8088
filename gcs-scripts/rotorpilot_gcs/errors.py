"""The errors of the helpers: every wait has a timeout, every refusal names what was refused."""
from __future__ import annotations

from .names import command_name, enum_name


class GcsError(Exception):
    """A failure of the link or of the vehicle (scripts report it as ``error: ...``, status 1)."""


class LinkTimeout(GcsError):
    """Nothing, or not the expected message, arrived in time."""


class CommandError(GcsError):
    """A command was not ACCEPTED (`result` is its MAV_RESULT) or its COMMAND_ACK never came
    (`result` is None); `reason` is the autopilot's STATUSTEXT about it, if any."""

    def __init__(self, command: int, result: int | None = None, reason: str | None = None) -> None:
        self.command, self.result, self.reason = command, result, reason
        what = f"{command_name(command)} ({command})"
        if result is None:
            msg = f"{what}: no COMMAND_ACK"
        else:
            msg = f"{what} refused: {enum_name('MAV_RESULT', result)}"
        if reason:
            msg += f" ({reason})"
        super().__init__(msg)


class ParamError(GcsError):
    """A parameter is unknown or a value was refused (the autopilot kept another one)."""


class MissionError(GcsError):
    """A plan transfer was refused: `result` is the MAV_MISSION_RESULT of the MISSION_ACK (None
    when the transfer failed otherwise)."""

    def __init__(self, message: str, result: int | None = None) -> None:
        self.result = result
        super().__init__(message)


class ModeError(GcsError, ValueError):
    """A mode the vehicle's personality has no name for (a PX4 name given to an ArduCopter
    vehicle, or the reverse): the message names the mode and the personality."""


class UsageError(GcsError):
    """A bad command line, option or input file (scripts exit with status 2)."""


class AutopilotStartError(GcsError):
    """`rotorpilot run` did not start: it exited or printed no ready line."""
