"""Shared helpers of the ground-station scripts: connect, wait, command-with-ACK, modes, parameters.

Every wait has a timeout and raises `LinkTimeout` when it expires; every command is followed by a
check of its COMMAND_ACK (`CommandError` names the command and the MAV_RESULT); parameters are
set byte-wise (INT32 bits in the float field) and the echoed PARAM_VALUE is checked (`ParamError`
when the autopilot kept another value, with its STATUSTEXT reason). Every request that waits for
an answer is sent again every `RESEND_S` until it comes or the timeout expires. Every message goes through
`recv()`, which also sends the GCS heartbeat once a second, streams the offboard setpoint when one
is set (`set_setpoint`) and prints each STATUSTEXT as ``autopilot: TEXT`` so refusals explain
themselves. `script_main()` turns these errors into ``error: ...`` on stderr and exit status 1
(`UsageError`: 2).
"""
import argparse
import collections
import math
import os
import struct
import sys
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

mavlink = mavutil.mavlink

DEFAULT_CONNECTION = "udpin:0.0.0.0:14550"
DEFAULT_TIMEOUT = 5.0
NAN = float("nan")
EARTH_RADIUS_M = 6371000.0

# PX4 custom modes: (main, sub).
POSCTL = (3, 0)
AUTO_TAKEOFF = (4, 2)
AUTO_LOITER = (4, 3)
AUTO_MISSION = (4, 4)
AUTO_RTL = (4, 5)
AUTO_LAND = (4, 6)
OFFBOARD = (6, 0)
MODE_NAMES = {
    (1, 0): "MANUAL", (2, 0): "ALTCTL", POSCTL: "POSCTL", (4, 1): "AUTO.READY", AUTO_TAKEOFF: "AUTO.TAKEOFF",
    AUTO_LOITER: "AUTO.LOITER", AUTO_MISSION: "AUTO.MISSION", AUTO_RTL: "AUTO.RTL", AUTO_LAND: "AUTO.LAND",
    OFFBOARD: "OFFBOARD", (7, 0): "STABILIZED", (8, 0): "ACRO",
}

# MAV_LANDED_STATE
ON_GROUND, IN_AIR, TAKEOFF, LANDING = 1, 2, 3, 4

# SET_POSITION_TARGET_LOCAL_NED type_mask: position + yaw (MAVSDK's set_position_ned).
POSITION_MASK = 2552
SETPOINT_RATE_HZ = 20.0
HEARTBEAT_PERIOD_S = 1.0
# A request whose answer has not come within this long is sent again (same content): UDP loses
# datagrams, and every request here is safe to repeat (PARAM_SET is idempotent, a repeated
# command is answered from the autopilot's cache, a repeated information request again).
RESEND_S = 1.0


class GcsError(Exception):
    """A failure the scripts report as ``error: ...`` with exit status 1."""


class LinkTimeout(GcsError):
    """Nothing (or not the expected message) arrived in time."""


class CommandError(GcsError):
    """A command was not ACCEPTED, or its COMMAND_ACK did not arrive."""

    def __init__(self, command, result=None, reason=None):
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
    """A parameter is unknown or a value was refused."""


class MissionError(GcsError):
    """A mission upload was refused or the mission failed."""


class UsageError(GcsError):
    """Bad command line or input file: exit status 2."""


def enum_name(enum, value):
    entry = mavlink.enums.get(enum, {}).get(value)
    return entry.name if entry is not None else f"{enum} {value}"


def command_name(command):
    return enum_name("MAV_CMD", command)


def mode_name(custom_mode):
    main, sub = (custom_mode >> 16) & 0xFF, (custom_mode >> 24) & 0xFF
    return MODE_NAMES.get((main, sub), f"mode {main}/{sub}")


def custom_mode(main, sub=0):
    return (main << 16) | (sub << 24)


def int32_bits(value):
    """Byte-wise INT32 in PARAM_SET's float field (PX4 and docs/mavlink.md §8.2)."""
    return struct.unpack("<f", struct.pack("<i", int(value)))[0]


def float_bits_to_int(value):
    return struct.unpack("<i", struct.pack("<f", value))[0]


def as_float32(value):
    return struct.unpack("<f", struct.pack("<f", value))[0]


class _State:
    """What the helpers keep per connection."""

    def __init__(self, timeout):
        self.timeout = timeout
        self.started = time.monotonic()
        self.last_heartbeat = -math.inf
        self.setpoint = None  # (x, y, z, yaw) LOCAL_NED while streaming
        self.last_setpoint = -math.inf
        self.latest = {}  # message type -> (monotonic arrival, message)
        self.texts = collections.deque(maxlen=20)  # (monotonic arrival, text)
        self.quiet_texts = False


def _state(conn):
    state = getattr(conn, "rp_state", None)
    if state is None:
        state = conn.rp_state = _State(DEFAULT_TIMEOUT)
    return state


def add_common_args(parser):
    parser.add_argument("--connection", default=DEFAULT_CONNECTION,
                        help=f"pymavlink connection string (default {DEFAULT_CONNECTION}, where `rotorpilot run` "
                             "sends its GCS telemetry)")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT,
                        help=f"seconds to wait for the autopilot's heartbeat and for each reply (default "
                             f"{DEFAULT_TIMEOUT:g})")
    return parser


def parser(description):
    """An ArgumentParser with --connection and --timeout."""
    return add_common_args(argparse.ArgumentParser(description=description,
                                                   formatter_class=argparse.RawDescriptionHelpFormatter))


def send_heartbeat(conn):
    conn.mav.heartbeat_send(mavlink.MAV_TYPE_GCS, mavlink.MAV_AUTOPILOT_INVALID, 0, 0, mavlink.MAV_STATE_ACTIVE)
    _state(conn).last_heartbeat = time.monotonic()


def _service(conn):
    """Sends what is due: the GCS heartbeat (1 Hz) and the offboard setpoint (20 Hz)."""
    state = _state(conn)
    now = time.monotonic()
    if now - state.last_heartbeat >= HEARTBEAT_PERIOD_S:
        send_heartbeat(conn)
    if state.setpoint is not None and now - state.last_setpoint >= 1.0 / SETPOINT_RATE_HZ:
        send_setpoint(conn)


def send_setpoint(conn):
    state = _state(conn)
    x, y, z, yaw = state.setpoint
    boot_ms = int((time.monotonic() - state.started) * 1000) & 0xFFFFFFFF
    conn.mav.set_position_target_local_ned_send(boot_ms, conn.target_system, conn.target_component,
                                                mavlink.MAV_FRAME_LOCAL_NED, POSITION_MASK, x, y, z,
                                                0, 0, 0, 0, 0, 0, yaw, 0)
    state.last_setpoint = time.monotonic()


def set_setpoint(conn, x, y, z, yaw=0.0):
    """Streams a LOCAL_NED position setpoint [m, rad] at 20 Hz from now on (while any helper waits)."""
    _state(conn).setpoint = (float(x), float(y), float(z), float(yaw))
    send_setpoint(conn)


def stop_setpoints(conn):
    _state(conn).setpoint = None


def print_statustext(msg, out=None):
    severity = enum_name("MAV_SEVERITY", msg.severity).replace("MAV_SEVERITY_", "").lower()
    print(f"autopilot: [{severity}] {msg.text}", file=out or sys.stdout, flush=True)


def recv(conn, timeout):
    """The next message from the autopilot within `timeout` s, or None. Keeps the link serviced:
    heartbeat, setpoint stream, STATUSTEXT printed, latest message of each type recorded."""
    state = _state(conn)
    deadline = time.monotonic() + timeout
    while True:
        _service(conn)
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return None
        step = min(remaining, 0.02 if state.setpoint is not None else 0.2)
        m = conn.recv_match(blocking=True, timeout=step)
        if m is None:
            continue
        kind = m.get_type()
        if kind.startswith("BAD_DATA") or kind.startswith("UNKNOWN"):
            continue
        if conn.target_system and m.get_srcSystem() != conn.target_system:
            continue
        now = time.monotonic()
        state.latest[kind] = (now, m)
        if kind == "STATUSTEXT":
            state.texts.append((now, m.text))
            if not state.quiet_texts:
                print_statustext(m)
        return m


def wait(conn, types, predicate=None, timeout=None, what=None):
    """The first message of `types` (a name or a list) satisfying `predicate`; LinkTimeout otherwise."""
    types = [types] if isinstance(types, str) else list(types)
    timeout = _state(conn).timeout if timeout is None else timeout
    deadline = time.monotonic() + timeout
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            raise LinkTimeout(f"timed out after {timeout:g} s waiting for {what or ' or '.join(types)}")
        m = recv(conn, remaining)
        if m is not None and m.get_type() in types and (predicate is None or predicate(m)):
            return m


def sleep(conn, seconds, on_message=None):
    """Keeps the link serviced for `seconds`, passing every message to `on_message`."""
    deadline = time.monotonic() + seconds
    while (remaining := deadline - time.monotonic()) > 0:
        m = recv(conn, remaining)
        if m is not None and on_message is not None:
            on_message(m)


def recent_text(conn, since, containing=None):
    """The latest STATUSTEXT that arrived after `since` (monotonic) and contains `containing`."""
    for t, text in reversed(_state(conn).texts):
        if t >= since and (containing is None or containing in text):
            return text
    return None


def connect(connection=DEFAULT_CONNECTION, timeout=DEFAULT_TIMEOUT):
    """Opens `connection` as GCS 255/190 and waits for an autopilot heartbeat (compid 1, not a GCS).
    Returns the connection with target_system/target_component set to the autopilot."""
    try:
        conn = mavutil.mavlink_connection(connection, source_system=255, source_component=190)
    except Exception as e:  # pymavlink raises plain Exceptions for bad strings, OSError for ports.
        raise GcsError(f"cannot open {connection}: {e}") from e
    conn.rp_state = _State(timeout)
    conn.target_system = 0
    deadline = time.monotonic() + timeout
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            conn.close()
            raise LinkTimeout(f"no autopilot heartbeat on {connection} within {timeout:g} s")
        m = recv(conn, remaining)
        if (m is not None and m.get_type() == "HEARTBEAT" and m.get_srcComponent() == mavlink.MAV_COMP_ID_AUTOPILOT1
                and m.type != mavlink.MAV_TYPE_GCS):
            break
    conn.target_system = m.get_srcSystem()
    conn.target_component = m.get_srcComponent()
    send_heartbeat(conn)
    kind = enum_name("MAV_TYPE", m.type).replace("MAV_TYPE_", "")
    armed = "armed" if m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED else "disarmed"
    print(f"connected to system {conn.target_system} ({kind}) in {mode_name(m.custom_mode)}, {armed}", flush=True)
    return conn


def command(conn, cmd_id, *params, timeout=None):
    """COMMAND_LONG with unset parameters NaN; returns the COMMAND_ACK when ACCEPTED, else raises
    CommandError naming the command and the MAV_RESULT (and the autopilot's STATUSTEXT if any).
    Retransmits once a second until answered: the autopilot answers repeats from its cache."""
    if len(params) > 7:
        raise ValueError("COMMAND_LONG has seven parameters")
    state = _state(conn)
    timeout = state.timeout if timeout is None else timeout
    p = [NAN if v is None else float(v) for v in params] + [NAN] * (7 - len(params))
    start = time.monotonic()
    deadline = start + timeout
    send_heartbeat(conn)
    sent = 0
    while True:
        now = time.monotonic()
        if now >= deadline:
            raise CommandError(cmd_id, None, f"nothing within {timeout:g} s")
        conn.mav.command_long_send(conn.target_system, conn.target_component, cmd_id, min(sent, 255), *p)
        sent += 1
        resend = min(deadline, time.monotonic() + 1.0)
        while (remaining := resend - time.monotonic()) > 0:
            m = recv(conn, remaining)
            if m is None or m.get_type() != "COMMAND_ACK" or m.command != cmd_id:
                continue
            if m.result == mavlink.MAV_RESULT_IN_PROGRESS:
                deadline = max(deadline, time.monotonic() + timeout)
                continue
            if m.result == mavlink.MAV_RESULT_ACCEPTED:
                return m
            reason = recent_text(conn, start)
            if reason is None:
                # The STATUSTEXT explaining a refusal may follow the ACK.
                try:
                    reason = wait(conn, "STATUSTEXT", timeout=0.3).text
                except LinkTimeout:
                    pass
            raise CommandError(cmd_id, m.result, reason)


def wait_heartbeat(conn, predicate, timeout=None, what="heartbeat"):
    return wait(conn, "HEARTBEAT", lambda m: m.get_srcComponent() == conn.target_component and predicate(m),
                timeout, what)


def is_armed(hb):
    return bool(hb.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED)


def set_mode(conn, main, sub=0, timeout=None):
    """DO_SET_MODE (custom-mode flag) and wait for the heartbeat to show the mode."""
    if isinstance(main, tuple):
        main, sub = main
    command(conn, mavlink.MAV_CMD_DO_SET_MODE, mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, main, sub, timeout=timeout)
    wanted = custom_mode(main, sub)
    wait_heartbeat(conn, lambda m: m.custom_mode == wanted, timeout,
                   f"heartbeat in {MODE_NAMES.get((main, sub), f'{main}/{sub}')}")


def arm(conn, timeout=None):
    command(conn, mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 1, timeout=timeout)
    wait_heartbeat(conn, is_armed, timeout, "an armed heartbeat")


def disarm(conn, timeout=None):
    command(conn, mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 0, timeout=timeout)
    wait_disarmed(conn, timeout)


def wait_disarmed(conn, timeout=None):
    return wait_heartbeat(conn, lambda m: not is_armed(m), timeout, "a disarmed heartbeat")


def wait_landed_state(conn, state, timeout=None):
    name = enum_name("MAV_LANDED_STATE", state)
    return wait(conn, "EXTENDED_SYS_STATE", lambda m: m.landed_state == state, timeout, f"landed state {name}")


def request_message(conn, msg_id, kind, timeout=None):
    """REQUEST_MESSAGE for `msg_id`; returns the `kind` message that answers it. Asks again every
    `RESEND_S` while the ACK came but the message did not (it was lost)."""
    timeout = _state(conn).timeout if timeout is None else timeout
    deadline = time.monotonic() + timeout
    while True:
        start = time.monotonic()
        command(conn, mavlink.MAV_CMD_REQUEST_MESSAGE, msg_id, timeout=max(deadline - start, 0.0))
        got = _state(conn).latest.get(kind)
        if got is not None and got[0] >= start:
            return got[1]
        remaining = deadline - time.monotonic()
        try:
            return wait(conn, kind, timeout=min(max(remaining, 0.0), RESEND_S))
        except LinkTimeout:
            if time.monotonic() >= deadline:
                raise LinkTimeout(f"timed out after {timeout:g} s waiting for {kind}") from None


def home_position(conn, timeout=None):
    """(lat_deg, lon_deg, alt_amsl_m) of home."""
    m = request_message(conn, mavlink.MAVLINK_MSG_ID_HOME_POSITION, "HOME_POSITION", timeout)
    return m.latitude * 1e-7, m.longitude * 1e-7, m.altitude * 1e-3


def local_position(conn, timeout=None):
    """A fresh LOCAL_POSITION_NED (it streams at 1 Hz only, so it is requested)."""
    return request_message(conn, mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED, "LOCAL_POSITION_NED", timeout)


def format_position(m):
    return f"north {m.x:+.2f} m, east {m.y:+.2f} m, up {-m.z:+.2f} m"


def takeoff(conn, height=None, timeout=None, climb_timeout=None):
    """NAV_TAKEOFF to `height` m above home (None: MIS_TAKEOFF_ALT), arm if disarmed, and wait until
    the take-off is complete (landed state IN_AIR). p7 is AMSL: home altitude + height."""
    if height is None:
        p7 = NAN
        height = param_get(conn, "MIS_TAKEOFF_ALT", timeout)
    else:
        p7 = home_position(conn, timeout)[2] + float(height)
    command(conn, mavlink.MAV_CMD_NAV_TAKEOFF, *([NAN] * 6), p7, timeout=timeout)
    hb = wait_heartbeat(conn, lambda m: True, timeout)
    if not is_armed(hb):
        arm(conn, timeout)
    climb = climb_timeout if climb_timeout is not None else 15.0 + 2.0 * float(height)
    wait_landed_state(conn, IN_AIR, climb)
    return height


def land(conn, timeout=None):
    command(conn, mavlink.MAV_CMD_NAV_LAND, timeout=timeout)


def _decode_param(m):
    if m.param_type in (mavlink.MAV_PARAM_TYPE_REAL32, mavlink.MAV_PARAM_TYPE_REAL64):
        return m.param_value
    return float_bits_to_int(m.param_value)


def _param_reply(conn, name, start, timeout, send):
    """Calls `send()` (again every `RESEND_S` until answered) and returns the PARAM_VALUE for
    `name`; a STATUSTEXT naming it without one means it is unknown."""
    deadline = time.monotonic() + timeout
    resend = time.monotonic()
    while (remaining := deadline - time.monotonic()) > 0:
        if time.monotonic() >= resend:
            send()
            resend = time.monotonic() + RESEND_S
        m = recv(conn, max(0.0, min(remaining, resend - time.monotonic())))
        if m is None:
            continue
        if m.get_type() == "PARAM_VALUE" and m.param_id == name:
            return m
        if m.get_type() == "STATUSTEXT" and name in m.text:
            # Unknown names get PARAM_ERROR (newer than pymavlink's dialect) and this STATUSTEXT.
            try:
                return wait(conn, "PARAM_VALUE", lambda p: p.param_id == name, timeout=0.3)
            except LinkTimeout:
                raise ParamError(f"{name}: {m.text}") from None
    reason = recent_text(conn, start, name)
    raise ParamError(f"{name}: no PARAM_VALUE within {timeout:g} s" + (f" ({reason})" if reason else ""))


def param_get(conn, name, timeout=None):
    """The value of parameter `name` (int for integer types)."""
    timeout = _state(conn).timeout if timeout is None else timeout
    start = time.monotonic()

    def send():
        conn.mav.param_request_read_send(conn.target_system, conn.target_component, name.encode(), -1)

    return _decode_param(_param_reply(conn, name, start, timeout, send))


def param_set(conn, name, value, int32=False, timeout=None):
    """Sets `name` (INT32 byte-wise when `int32`) and checks the echo; ParamError when the autopilot
    keeps another value (a refusal) or does not know the name. Returns the echoed value."""
    timeout = _state(conn).timeout if timeout is None else timeout
    if int32:
        if int(value) != value:
            raise ParamError(f"{name}: {value} is not an integer")
        wanted, raw, ptype = int(value), int32_bits(value), mavlink.MAV_PARAM_TYPE_INT32
    else:
        wanted = raw = as_float32(float(value))
        ptype = mavlink.MAV_PARAM_TYPE_REAL32
    start = time.monotonic()

    def send():
        conn.mav.param_set_send(conn.target_system, conn.target_component, name.encode(), raw, ptype)

    echo = _param_reply(conn, name, start, timeout, send)
    got = _decode_param(echo)
    if got != wanted:
        reason = recent_text(conn, start, name)
        if reason is None:
            try:
                reason = wait(conn, "STATUSTEXT", lambda m: name in m.text, timeout=0.5).text
            except LinkTimeout:
                pass
        raise ParamError(f"{name} = {value} refused: the autopilot kept {got}" + (f" ({reason})" if reason else ""))
    return got


def script_main(fn):
    """Runs `fn()` and exits: its return value (0 if None), 1 on a GcsError, 2 on a UsageError."""
    try:
        code = fn()
    except UsageError as e:
        print(f"error: {e}", file=sys.stderr, flush=True)
        sys.exit(2)
    except (GcsError, OSError) as e:
        print(f"error: {e}", file=sys.stderr, flush=True)
        sys.exit(1)
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr, flush=True)
        sys.exit(130)
    sys.exit(code or 0)
