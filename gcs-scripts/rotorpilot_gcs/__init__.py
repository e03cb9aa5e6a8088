"""rotorpilot-gcs: ground-station helpers for `rotorpilot run` (and PX4 SITL) over pymavlink, and
a pytest plugin that starts the autopilot for scripted mission tests.

Two objects: a `Vehicle` is one autopilot over one pymavlink connection, the link and the
helpers' state of it, with the library's calls as methods; an `Autopilot` is a started
``rotorpilot run`` process, which hands out the `Vehicle` it flies (``autopilot.vehicle``).
Every wait has a timeout (`LinkTimeout`), every command is checked against its COMMAND_ACK
(`CommandError`), every parameter against its echo (`ParamError`), every plan transfer against
its MISSION_ACK (`MissionError`); requests are sent again while unanswered. A background thread
sends the GCS heartbeat (1 Hz) and an offboard setpoint stream (20 Hz, `set_setpoint`) whatever
the script does, and each STATUSTEXT read is printed as ``autopilot: [severity] text``.

    from rotorpilot_gcs import Vehicle

    vehicle = Vehicle.connect("udpin:0.0.0.0:14550")   # a running autopilot's GCS telemetry
    vehicle.takeoff(3.0)                               # NAV_TAKEOFF, arm, wait until in the air
    vehicle.land()
    vehicle.wait_disarmed(30)

The calls are the functions of the submodules, taking the pymavlink connection (`connect`
returns one): `link` (recv, wait, sleep, latest), `commands`, `flight` (set_mode, arm, takeoff,
land), `telemetry` (wait_*, local_position, home_position), `params`, `missions` (the plan
protocol and `MissionItem` builders), `plans` (plan files), `offboard`, `geo`, `cli` (the
scripts' argument parser). The pytest plugin (``rotorpilot_gcs.pytest_plugin``) provides the
fixtures ``autopilot``, ``vehicle``, ``autopilot_factory``, ``rotorpilot_bin`` and ``rotorpilot``.
"""
from . import cli, commands, flight, geo, link, missions, modes, names, offboard, params, plans, process, telemetry
from ._mav import connection_with_dialect, mavlink, mavutil
from .errors import AutopilotStartError, CommandError, GcsError, LinkTimeout, MissionError, ParamError, UsageError
from .link import DEFAULT_CONNECTION, DEFAULT_TIMEOUT, Connection, Message, connect
from .modes import (
    AUTO_LAND,
    AUTO_LOITER,
    AUTO_MISSION,
    AUTO_RTL,
    AUTO_TAKEOFF,
    OFFBOARD,
    POSCTL,
    PX4_MODES,
    Mode,
    custom_mode,
    mode_name,
    parse_mode,
)
from .process import Autopilot, find_binary, free_port
from .vehicle import Vehicle

__version__ = "0.1.0"

__all__ = [
    # The entry points.
    "Autopilot", "Vehicle", "connect", "find_binary", "free_port", "Connection", "Message", "DEFAULT_CONNECTION",
    "DEFAULT_TIMEOUT",
    # Errors.
    "GcsError", "AutopilotStartError", "CommandError", "LinkTimeout", "MissionError", "ParamError", "UsageError",
    # PX4's modes.
    "Mode", "OFFBOARD", "POSCTL", "AUTO_LAND", "AUTO_LOITER", "AUTO_MISSION", "AUTO_RTL", "AUTO_TAKEOFF",
    "PX4_MODES", "custom_mode", "mode_name", "parse_mode",
    # pymavlink, for MAVLink 2.
    "mavlink", "mavutil", "connection_with_dialect",
    # The submodules.
    "cli", "commands", "flight", "geo", "link", "missions", "modes", "names", "offboard", "params", "plans", "process",
    "telemetry",
]
