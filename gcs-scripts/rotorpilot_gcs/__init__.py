"""rotorpilot-gcs: ground-station helpers for `rotorpilot run` (and PX4 SITL) over pymavlink, and
a pytest plugin that starts the autopilot for scripted mission tests.

Functions take a pymavlink connection from `connect` (``conn``); `Vehicle` and `Autopilot` (a
started ``rotorpilot run``) have them as methods. Every wait has a timeout (`LinkTimeout`), every
command is checked against its COMMAND_ACK (`CommandError`), every parameter against its echo
(`ParamError`), every plan transfer against its MISSION_ACK (`MissionError`); requests are sent
again while unanswered. While any helper reads the link, the GCS heartbeat (1 Hz) and an offboard
setpoint stream (20 Hz, `set_setpoint`) go out, and each STATUSTEXT is printed as
``autopilot: [severity] text``.

    from rotorpilot_gcs import Autopilot, connect, takeoff, land, wait_disarmed

    conn = connect("udpin:0.0.0.0:14550")   # a running autopilot's GCS telemetry
    takeoff(conn, 3.0)                      # NAV_TAKEOFF, arm, wait until in the air
    land(conn)
    wait_disarmed(conn, 30)

The pytest plugin (``rotorpilot_gcs.pytest_plugin``) provides the fixtures ``autopilot``,
``autopilot_factory``, ``rotorpilot_bin`` and ``rotorpilot``.
"""
from ._mav import connection_with_dialect, mavlink, mavutil
from .cli import add_common_args, parser, script_main
from .commands import ACK_TIMEOUT_S, NAN, command, command_ack, request_message
from .errors import AutopilotStartError, CommandError, GcsError, LinkTimeout, MissionError, ParamError, UsageError
from .flight import FORCE, arm, disarm, land, return_to_launch, set_mode, takeoff
from .geo import DEFAULT_HOME, EARTH_RADIUS_M, deg_e7_per_metre, global_to_offset, offset_to_global
from .link import (
    DEFAULT_CONNECTION,
    DEFAULT_TIMEOUT,
    ONE_SHOT,
    RESEND_S,
    Connection,
    Message,
    connect,
    forget,
    keep,
    latest,
    link_state,
    print_statustext,
    recent_text,
    recv,
    send_heartbeat,
    set_heartbeats,
    set_periodic,
    sleep,
    stop_periodic,
    wait,
)
from .missions import (
    ALL,
    FENCE,
    MISSION,
    RALLY,
    MissionItem,
    clear_mission,
    download_mission,
    item_from_message,
    nav_land,
    nav_return_to_launch,
    nav_takeoff,
    nav_waypoint,
    upload_mission,
)
from .modes import (
    AUTO_LAND,
    AUTO_LOITER,
    AUTO_MISSION,
    AUTO_RTL,
    AUTO_TAKEOFF,
    MODE_NAMES,
    OFFBOARD,
    POSCTL,
    PX4_MODES,
    Mode,
    custom_mode,
    mode_name,
    mode_of,
    parse_mode,
)
from .names import command_name, enum_name
from .offboard import POSITION_MASK, SETPOINT_RATE_HZ, set_setpoint, stop_setpoints
from .params import as_float32, float_bits_to_int, int32_bits, param_get, param_list, param_set, param_value
from .plans import QgcPlan, load_plan, load_qgc_plan, load_wpl, plan_items, qgc_plan_items
from .process import Autopilot, checkout_binary, find_binary, free_port
from .telemetry import (
    IN_AIR,
    LANDING,
    ON_GROUND,
    TAKEOFF,
    format_position,
    home_position,
    is_armable,
    is_armed,
    local_position,
    wait_armable,
    wait_armed,
    wait_disarmed,
    wait_heartbeat,
    wait_in_air,
    wait_landed_state,
    wait_mode,
    wait_on_ground,
)
from .vehicle import Vehicle

__version__ = "0.1.0"

__all__ = [
    "ACK_TIMEOUT_S", "ALL", "AUTO_LAND", "AUTO_LOITER", "AUTO_MISSION", "AUTO_RTL", "AUTO_TAKEOFF", "Autopilot",
    "AutopilotStartError", "CommandError", "Connection", "DEFAULT_CONNECTION", "DEFAULT_HOME", "DEFAULT_TIMEOUT",
    "EARTH_RADIUS_M", "FENCE", "FORCE", "GcsError", "IN_AIR", "LANDING", "LinkTimeout", "MISSION", "MODE_NAMES",
    "Message", "MissionError", "MissionItem", "Mode", "NAN", "OFFBOARD", "ONE_SHOT", "ON_GROUND", "POSCTL",
    "POSITION_MASK", "PX4_MODES", "ParamError", "QgcPlan", "RALLY", "RESEND_S", "SETPOINT_RATE_HZ", "TAKEOFF",
    "UsageError", "Vehicle", "add_common_args", "arm", "as_float32", "clear_mission", "command", "command_ack",
    "command_name", "connect", "connection_with_dialect", "custom_mode", "deg_e7_per_metre", "disarm",
    "download_mission", "enum_name", "checkout_binary", "find_binary", "float_bits_to_int", "forget",
    "format_position", "free_port", "global_to_offset", "home_position",
    "int32_bits", "is_armable", "is_armed", "item_from_message", "keep", "land", "latest", "link_state", "load_plan",
    "load_qgc_plan", "load_wpl", "local_position", "mavlink", "mavutil", "mode_name", "mode_of", "nav_land",
    "nav_return_to_launch", "nav_takeoff", "nav_waypoint", "offset_to_global", "param_get", "param_list", "param_set",
    "param_value", "parse_mode", "parser", "plan_items", "print_statustext", "qgc_plan_items", "recent_text", "recv",
    "request_message", "return_to_launch", "script_main", "send_heartbeat", "set_heartbeats", "set_mode",
    "set_periodic", "set_setpoint", "sleep", "stop_periodic", "stop_setpoints", "takeoff", "upload_mission", "wait",
    "wait_armable", "wait_armed", "wait_disarmed", "wait_heartbeat", "wait_in_air", "wait_landed_state", "wait_mode",
    "wait_on_ground",
]
