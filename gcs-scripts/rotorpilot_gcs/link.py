"""The link to one autopilot: connect, receive, wait, and what a ground station sends unasked.

What a ground station sends unasked (the GCS heartbeat once a second, an offboard setpoint
stream: `set_periodic`) goes out from a background thread, the keeper, every `KEEPER_PERIOD_S`
on every link the helpers know, as MAVSDK serves its link: user code may block, sleep or compute
between calls without tripping the autopilot's link-loss or offboard-loss failsafe. `recv`
sends what is due too, first; it drops messages of other systems than the target and
undecodable ones, records the latest message of each type (`latest`) and each parameter's type,
and prints each STATUSTEXT as ``autopilot: [severity] text``.

What the helpers know of each link is one `LinkState` (a dataclass: time-out, periodic sends,
latest messages, texts, kept messages, parameter types), held in a registry keyed weakly by the
pymavlink connection (`link_state`; nothing is set on pymavlink's object) and by the `Vehicle` of
that connection; `forget` drops it.

Every wait has a timeout and raises `LinkTimeout` when it expires. Helpers that wait for their
own answer (commands, parameters, plan transfers) keep the one-shot messages they read past
(`ONE_SHOT`: a STATUSTEXT may overtake a COMMAND_ACK) for the next `wait`, which looks at those
first; a `wait` that does not find its message among them drops them and reads new ones.
"""
from __future__ import annotations

import collections
import dataclasses
import math
import sys
import threading
import time
import weakref
from typing import Any, Callable, Iterable, TextIO, Union

from ._mav import mavlink, mavutil
from .errors import GcsError, LinkTimeout
from .modes import ARDUPILOT, PERSONALITY_NAMES, personality_of, vehicle_mode_name
from .names import enum_name

#: A pymavlink connection (``mavutil.mavfile``; pymavlink has no type hints).
Connection = Any
#: A decoded pymavlink message.
Message = Any
#: One message type name or several.
Types = Union[str, Iterable[str]]

#: Where `rotorpilot run` (and PX4 SITL) sends its GCS telemetry.
DEFAULT_CONNECTION = "udpin:0.0.0.0:14550"
#: Seconds to wait for the autopilot's heartbeat and for each reply.
DEFAULT_TIMEOUT = 5.0
#: The GCS heartbeat period [s].
HEARTBEAT_PERIOD_S = 1.0
#: A request whose answer has not come within this long [s] is sent again (same content): UDP
#: loses datagrams, and every request here is safe to repeat (PARAM_SET is idempotent, a repeated
#: command is answered from the autopilot's cache, a repeated information request again).
RESEND_S = 1.0
#: Message types that come once (events and replies), kept for `wait` when a helper reads past them.
ONE_SHOT = frozenset({"STATUSTEXT", "MISSION_ITEM_REACHED", "PARAM_VALUE", "AUTOPILOT_VERSION", "MESSAGE_INTERVAL"})
#: At most this many kept one-shot messages (the oldest go first).
PENDING_MAX = 100
#: STATUSTEXTs kept for `recent_text`.
TEXTS_MAX = 20
#: The ids a ground station uses (QGroundControl's).
GCS_SYSTEM, GCS_COMPONENT = 255, 190
#: How often the keeper thread sends what is due [s] (the 20 Hz setpoint stream needs 50 ms).
KEEPER_PERIOD_S = 0.01
#: The rate [Hz] of every stream group an ArduCopter vehicle is asked for on connect
#: (REQUEST_DATA_STREAM ALL; MAVProxy's default rate): Copter streams nothing but its HEARTBEAT
#: until asked. Rates count the vehicle's (simulated) time.
STREAM_RATE_HZ = 4
#: Messages of Copter's stream groups that tell the streams started.
STREAMED = frozenset({"SYS_STATUS", "GPS_RAW_INT", "GLOBAL_POSITION_INT", "ATTITUDE", "VFR_HUD", "EKF_STATUS_REPORT"})


@dataclasses.dataclass
class Periodic:
    """A message a link sends unasked every `period_s` (the keeper thread calls `send`)."""

    period_s: float
    #: When it last went out (``time.monotonic()``; ``-inf``: never, due at once).
    last_sent: float
    send: Callable[[], None]


@dataclasses.dataclass
class LinkState:
    """Everything the helpers keep about one link: held in a registry keyed by the pymavlink
    connection (`link_state`), and by the `Vehicle` of that connection (``vehicle.state``)."""

    #: The default time-out of this link's waits [s].
    timeout: float = DEFAULT_TIMEOUT
    #: When the link was first used (``time.monotonic()``; the setpoints' ``time_boot_ms`` count from it).
    started: float = dataclasses.field(default_factory=time.monotonic)
    #: What goes out unasked, by name (``"heartbeat"``, ``"setpoint"``).
    periodic: dict[str, Periodic] = dataclasses.field(default_factory=dict)
    #: The latest message of each type and when it came (``time.monotonic()``).
    latest: dict[str, tuple[float, Message]] = dataclasses.field(default_factory=dict)
    #: The last `TEXTS_MAX` STATUSTEXTs and when they came.
    texts: collections.deque[tuple[float, str]] = dataclasses.field(
        default_factory=lambda: collections.deque(maxlen=TEXTS_MAX))
    #: One-shot messages a helper read past, for the next `wait`.
    pending: list[Message] = dataclasses.field(default_factory=list)
    #: Each parameter's MAV_PARAM_TYPE as the autopilot declared it.
    param_types: dict[str, int] = dataclasses.field(default_factory=dict)
    #: Whether `recv` prints each STATUSTEXT.
    print_texts: bool = True
    #: The autopilot's HEARTBEAT.autopilot (MAV_AUTOPILOT; 3 ArduPilot, 12 PX4) once heard, else
    #: None: the vehicle's personality (`personality`).
    autopilot: int | None = None
    #: The rate [Hz] an ArduCopter vehicle's streams are asked for once it is known to be one
    #: (`request_streams`; None: never asked by the helpers).
    stream_rate_hz: int | None = STREAM_RATE_HZ
    #: Whether the helpers asked for the streams (an ArduCopter vehicle).
    streams_requested: bool = False
    #: Held while the periodic sends change or go out (the keeper thread and the caller's).
    lock: threading.RLock = dataclasses.field(default_factory=threading.RLock, repr=False, compare=False)


#: Every connection with helper state, and that state: `recv` on any of them and the keeper
#: thread service them all. Keyed weakly: a connection dropped by its user goes with its state.
_STATES: weakref.WeakKeyDictionary[Connection, LinkState] = weakref.WeakKeyDictionary()
#: Held while `_STATES` changes or is copied (the keeper thread reads it).
_states_guard = threading.Lock()


def link_state(conn: Connection) -> LinkState:
    """The helpers' state of `conn`, created (GCS heartbeat on, `DEFAULT_TIMEOUT`) on first use."""
    with _states_guard:
        state = _STATES.get(conn)
        if state is None:
            state = _STATES[conn] = LinkState()
            state.periodic["heartbeat"] = Periodic(HEARTBEAT_PERIOD_S, -math.inf, weak_sender(conn, _heartbeat))
    _start_keeper()
    return state


def _links() -> list[tuple[Connection, LinkState]]:
    """A copy of the registry: every known link and its state."""
    with _states_guard:
        return list(_STATES.items())


_keeper: threading.Thread | None = None
_keeper_guard = threading.Lock()


def _keep_links() -> None:
    """The keeper thread: sends what is due on every known link, for ever (a daemon)."""
    while True:
        time.sleep(KEEPER_PERIOD_S)
        _service_links()


def _service_links() -> None:
    """One round of the keeper (a function of its own: no connection stays referenced while the
    keeper sleeps, so a dropped one can go)."""
    for conn, state in _links():
        try:
            _service(conn, state)
        except (OSError, ValueError, AttributeError):
            # Closed under us: leave it alone from now on.
            forget(conn)


def _start_keeper() -> None:
    global _keeper
    with _keeper_guard:
        if _keeper is None or not _keeper.is_alive():
            _keeper = threading.Thread(target=_keep_links, name="rotorpilot-gcs-keeper", daemon=True)
            _keeper.start()


def _heartbeat(conn: Connection) -> None:
    conn.mav.heartbeat_send(mavlink.MAV_TYPE_GCS, mavlink.MAV_AUTOPILOT_INVALID, 0, 0, mavlink.MAV_STATE_ACTIVE)


def weak_sender(conn: Connection, send: Callable[[Connection], None]) -> Callable[[], None]:
    """``send(conn)`` as a periodic sender that does not keep `conn` alive (the registry holds
    each link's state only while its connection lives)."""
    ref = weakref.ref(conn)

    def send_if_alive() -> None:
        alive = ref()
        if alive is not None:
            send(alive)

    return send_if_alive


def send_heartbeat(conn: Connection) -> None:
    """Sends a GCS heartbeat now (also when the periodic one is off)."""
    state = link_state(conn)
    with state.lock:
        _heartbeat(conn)
        beat = state.periodic.get("heartbeat")
        if beat is not None:
            beat.last_sent = time.monotonic()


def set_heartbeats(conn: Connection, enabled: bool) -> None:
    """Turns the GCS heartbeat `recv` sends once a second on or off (off: the autopilot's
    data-link-loss failsafe can be tested)."""
    state = link_state(conn)
    with state.lock:
        if enabled:
            state.periodic.setdefault("heartbeat",
                                      Periodic(HEARTBEAT_PERIOD_S, -math.inf, weak_sender(conn, _heartbeat)))
        else:
            state.periodic.pop("heartbeat", None)


def set_periodic(conn: Connection, name: str, period_s: float, send: Callable[[], None]) -> None:
    """Calls `send()` now and then every `period_s` [s] (from the keeper thread), until
    `stop_periodic(conn, name)`; a second stream of the same `name` replaces the first."""
    state = link_state(conn)
    with state.lock:
        send()
        state.periodic[name] = Periodic(period_s, time.monotonic(), send)


def stop_periodic(conn: Connection, name: str) -> None:
    """Stops the periodic sender `name` (nothing when there is none)."""
    state = link_state(conn)
    with state.lock:
        state.periodic.pop(name, None)


def _service(conn: Connection, state: LinkState) -> None:
    with state.lock:
        now = time.monotonic()
        for entry in list(state.periodic.values()):
            if now - entry.last_sent >= entry.period_s:
                entry.send()
                entry.last_sent = time.monotonic()


def service(conn: Connection) -> None:
    """Sends what is due now on `conn`: the GCS heartbeat and every periodic stream."""
    _service(conn, link_state(conn))


def forget(conn: Connection) -> None:
    """Drops `conn` and its state from the helpers' registry: neither the keeper thread nor other
    links' waits service it any more (call it before closing `conn`)."""
    with _states_guard:
        _STATES.pop(conn, None)


def service_all(conn: Connection) -> None:
    """`service` on `conn`, then on every other connection the helpers know; one that cannot
    send any more (closed) is forgotten."""
    service(conn)
    for other, state in _links():
        if other is conn:
            continue
        try:
            _service(other, state)
        except OSError:
            forget(other)


def print_statustext(msg: Message, out: TextIO | None = None) -> None:
    """Prints a STATUSTEXT as ``autopilot: [severity] text``."""
    severity = enum_name("MAV_SEVERITY", msg.severity).replace("MAV_SEVERITY_", "").lower()
    print(f"autopilot: [{severity}] {msg.text}", file=out or sys.stdout, flush=True)


def recv(conn: Connection, timeout: float) -> Message | None:
    """The next message from the autopilot within `timeout` [s], or None; keeps the link
    serviced meanwhile (see the module's description)."""
    state = link_state(conn)
    deadline = time.monotonic() + timeout
    while True:
        service_all(conn)
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return None
        fastest = min((entry.period_s for _, other in _links() for entry in other.periodic.values()), default=1.0)
        m = conn.recv_match(blocking=True, timeout=min(remaining, 0.02 if fastest < 0.2 else 0.2))
        if m is None:
            continue
        kind = m.get_type()
        if kind.startswith("BAD_DATA") or kind.startswith("UNKNOWN"):
            continue
        if conn.target_system and m.get_srcSystem() != conn.target_system:
            continue
        now = time.monotonic()
        state.latest[kind] = (now, m)
        if kind == "PARAM_VALUE":
            state.param_types[m.param_id] = m.param_type
        elif kind == "HEARTBEAT" and _is_autopilot(m) and m.get_srcSystem() == conn.target_system:
            state.autopilot = m.autopilot
        elif kind == "STATUSTEXT":
            state.texts.append((now, m.text))
            if state.print_texts:
                print_statustext(m)
        return m


def keep(conn: Connection, m: Message) -> None:
    """Keeps `m` for the next `wait` if it is one-shot (helpers call this for what they read past)."""
    if m.get_type() in ONE_SHOT:
        pending = link_state(conn).pending
        pending.append(m)
        del pending[:-PENDING_MAX]


def _names(types: Types) -> list[str]:
    return [types] if isinstance(types, str) else list(types)


def wait(conn: Connection, types: Types, predicate: Callable[[Message], Any] | None = None,
         timeout: float | None = None, what: str | None = None) -> Message:
    """The first message of `types` (a name or several) satisfying `predicate`, looking first at
    the one-shot messages helpers kept; `LinkTimeout` (naming `what`) after `timeout` [s]
    (default: the connection's timeout)."""
    names = _names(types)
    state = link_state(conn)
    for i, m in enumerate(state.pending):
        if m.get_type() in names and (predicate is None or predicate(m)):
            del state.pending[: i + 1]
            return m
    state.pending.clear()
    timeout = state.timeout if timeout is None else timeout
    deadline = time.monotonic() + timeout
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            raise LinkTimeout(f"timed out after {timeout:g} s waiting for {what or ' or '.join(names)}")
        m = recv(conn, remaining)
        if m is not None and m.get_type() in names and (predicate is None or predicate(m)):
            return m


def sleep(conn: Connection, seconds: float, on_message: Callable[[Message], Any] | None = None) -> None:
    """Keeps the link serviced for `seconds`, passing every message to `on_message`."""
    deadline = time.monotonic() + seconds
    while (remaining := deadline - time.monotonic()) > 0:
        m = recv(conn, remaining)
        if m is not None and on_message is not None:
            on_message(m)


def recent_text(conn: Connection, since: float, containing: str | None = None) -> str | None:
    """The latest STATUSTEXT that arrived after `since` (``time.monotonic()``) and contains
    `containing`, or None."""
    for t, text in reversed(link_state(conn).texts):
        if t >= since and (containing is None or containing in text):
            return text
    return None


def latest(conn: Connection, kind: str, since: float | None = None) -> Message | None:
    """The latest `kind` message received (after `since`, ``time.monotonic()``), or None."""
    got = link_state(conn).latest.get(kind)
    if got is None or (since is not None and got[0] < since):
        return None
    return got[1]


def _is_autopilot(m: Message) -> bool:
    """Whether a HEARTBEAT is an autopilot's (component 1, not a GCS)."""
    return bool(m.get_srcComponent() == mavlink.MAV_COMP_ID_AUTOPILOT1 and m.type != mavlink.MAV_TYPE_GCS)


def personality(conn: Connection, timeout: float | None = None) -> str:
    """The vehicle's personality, ``"px4"`` or ``"ardupilot"`` (`modes.PX4`, `modes.ARDUPILOT`),
    from its HEARTBEAT's autopilot field (waited for, up to `timeout` [s], if none was heard).
    The first time an ArduCopter vehicle is known, its streams are asked for (`request_streams`
    at the link's `stream_rate_hz`): Copter sends nothing but its HEARTBEAT until asked."""
    state = link_state(conn)
    if state.autopilot is None:
        timeout = state.timeout if timeout is None else timeout
        deadline = time.monotonic() + timeout
        while state.autopilot is None:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise LinkTimeout(f"timed out after {timeout:g} s waiting for the autopilot's heartbeat")
            m = recv(conn, remaining)
            if m is not None:
                keep(conn, m)
    kind = personality_of(state.autopilot)
    if kind == ARDUPILOT and not state.streams_requested and state.stream_rate_hz:
        request_streams(conn, state.stream_rate_hz, timeout)
    return kind


def request_streams(conn: Connection, rate_hz: int = STREAM_RATE_HZ, timeout: float | None = None) -> None:
    """REQUEST_DATA_STREAM ALL at `rate_hz` [Hz] (0 stops them), as MAVProxy and DroneKit ask an
    ArduPilot vehicle: every stream group but PARAMS at that rate on this link. Sent again every
    `RESEND_S` until a streamed message comes (there is no answer; UDP may lose the request)."""
    state = link_state(conn)
    state.streams_requested = True
    timeout = state.timeout if timeout is None else timeout
    deadline = time.monotonic() + timeout

    def send() -> None:
        conn.mav.request_data_stream_send(conn.target_system, conn.target_component, mavlink.MAV_DATA_STREAM_ALL,
                                          int(rate_hz), 1 if rate_hz else 0)

    send()
    if not rate_hz:
        return
    resend = time.monotonic() + RESEND_S
    while (remaining := deadline - time.monotonic()) > 0:
        m = recv(conn, min(remaining, max(0.0, resend - time.monotonic())))
        if m is not None:
            if m.get_type() in STREAMED:
                return
            keep(conn, m)
        if time.monotonic() >= resend:
            send()
            resend = time.monotonic() + RESEND_S
    raise LinkTimeout(f"timed out after {timeout:g} s waiting for the streams asked for (REQUEST_DATA_STREAM)")


def connect(connection: str | Connection = DEFAULT_CONNECTION, timeout: float = DEFAULT_TIMEOUT, *,
            target_system: int | None = None, source_system: int = GCS_SYSTEM,
            source_component: int = GCS_COMPONENT, quiet: bool = False,
            stream_rate_hz: int | None = STREAM_RATE_HZ) -> Connection:
    """Opens `connection` (a pymavlink connection string, or an open pymavlink connection) as a
    GCS and waits for an autopilot's heartbeat (component 1, not a GCS; of `target_system` if
    given). Returns the connection with target_system/target_component set to that autopilot;
    prints ``connected to system 1 (QUADROTOR) in AUTO.LOITER, disarmed`` (``(QUADROTOR,
    ArduCopter) in STABILIZE`` for an ArduCopter vehicle) unless `quiet`.
    The heartbeat tells the personality (`personality`): an ArduCopter vehicle is asked for its
    streams at `stream_rate_hz` [Hz] (`request_streams`; None: not asked).
    `GcsError` when the string cannot be opened, `LinkTimeout` without a heartbeat."""
    if isinstance(connection, str):
        try:
            conn = mavutil.mavlink_connection(connection, source_system=source_system,
                                              source_component=source_component)
        except Exception as e:  # pymavlink raises plain Exceptions for bad strings, OSError for ports.
            raise GcsError(f"cannot open {connection}: {e}") from e
        name = connection
    else:
        conn, name = connection, getattr(connection, "address", "the connection")
    state = link_state(conn)
    state.timeout = timeout
    conn.target_system = target_system or 0
    deadline = time.monotonic() + timeout
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            if isinstance(connection, str):
                forget(conn)
                conn.close()
            raise LinkTimeout(f"no autopilot heartbeat on {name} within {timeout:g} s")
        m = recv(conn, remaining)
        if m is not None and m.get_type() == "HEARTBEAT" and _is_autopilot(m):
            break
    conn.target_system = m.get_srcSystem()
    conn.target_component = m.get_srcComponent()
    state.autopilot = m.autopilot
    state.stream_rate_hz = stream_rate_hz
    if "heartbeat" in state.periodic:
        send_heartbeat(conn)
    face = personality(conn, timeout)
    if not quiet:
        kind = enum_name("MAV_TYPE", m.type).replace("MAV_TYPE_", "")
        armed = "armed" if m.base_mode & mavlink.MAV_MODE_FLAG_SAFETY_ARMED else "disarmed"
        face_name = "" if face != ARDUPILOT else f", {PERSONALITY_NAMES[face]}"
        print(f"connected to system {conn.target_system} ({kind}{face_name}) in "
              f"{vehicle_mode_name(face, m.custom_mode)}, {armed}", flush=True)
    return conn
