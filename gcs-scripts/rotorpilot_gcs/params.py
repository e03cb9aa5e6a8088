"""Parameters (PARAM_REQUEST_READ / PARAM_SET and the PARAM_VALUE echo).

Integer parameters travel byte-wise on PX4: the INT32's four bytes in PARAM_SET's and
PARAM_VALUE's float field (PX4's convention), so `param_set` and `param_get` convert with
`int32_bits` and `float_bits_to_int`; on ArduCopter (`link.personality`) they travel cast, the
number as a float (PARAM_ENCODE_C_CAST), with the type the vehicle declares (INT8, INT16 …).
A value the autopilot refuses is echoed unchanged (`ParamError` then names the value kept and
the autopilot's STATUSTEXT); an unknown name gets a STATUSTEXT naming it.
"""
from __future__ import annotations

import struct
import time
from typing import Callable

from ._mav import mavlink
from .errors import LinkTimeout, ParamError
from .link import RESEND_S, Connection, Message, keep, link_state, personality, recent_text, recv, wait
from .modes import ARDUPILOT

#: The integer MAV_PARAM_TYPEs (sent byte-wise in the float field).
INTEGER_TYPES = frozenset({mavlink.MAV_PARAM_TYPE_UINT8, mavlink.MAV_PARAM_TYPE_INT8, mavlink.MAV_PARAM_TYPE_UINT16,
                           mavlink.MAV_PARAM_TYPE_INT16, mavlink.MAV_PARAM_TYPE_UINT32, mavlink.MAV_PARAM_TYPE_INT32})


def int32_bits(value: int) -> float:
    """The float whose four bytes are the INT32 `value` (what PARAM_SET carries for an integer)."""
    return float(struct.unpack("<f", struct.pack("<i", int(value)))[0])


def float_bits_to_int(value: float) -> int:
    """The INT32 whose four bytes are the float `value` (an integer PARAM_VALUE's value)."""
    return int(struct.unpack("<i", struct.pack("<f", value))[0])


def as_float32(value: float) -> float:
    """`value` rounded to the nearest float32 (what a REAL32 parameter holds)."""
    return float(struct.unpack("<f", struct.pack("<f", value))[0])


def param_value(m: Message, cast: bool = False) -> float | int:
    """The value of a PARAM_VALUE: an int for the integer types (its bytes, or with `cast` the
    number, ArduPilot's encoding), else the float."""
    if m.param_type in INTEGER_TYPES:
        return int(m.param_value) if cast else float_bits_to_int(m.param_value)
    return float(m.param_value)


def _cast(conn: Connection) -> bool:
    """Whether the vehicle casts integer parameters to float (ArduPilot) rather than sending their bytes."""
    return personality(conn) == ARDUPILOT


def _param_reply(conn: Connection, name: str, start: float, timeout: float, send: Callable[[], None]) -> Message:
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
        keep(conn, m)
        if m.get_type() == "STATUSTEXT" and name in m.text:
            # Unknown names get PARAM_ERROR (newer than pymavlink's dialect) and this STATUSTEXT.
            try:
                return wait(conn, "PARAM_VALUE", lambda p: p.param_id == name, timeout=0.3)
            except LinkTimeout:
                raise ParamError(f"{name}: {m.text}") from None
    reason = recent_text(conn, start, name)
    raise ParamError(f"{name}: no PARAM_VALUE within {timeout:g} s" + (f" ({reason})" if reason else ""))


def _read(conn: Connection, name: str, timeout: float | None) -> Message:
    timeout = link_state(conn).timeout if timeout is None else timeout

    def send() -> None:
        conn.mav.param_request_read_send(conn.target_system, conn.target_component, name.encode(), -1)

    return _param_reply(conn, name, time.monotonic(), timeout, send)


def param_get(conn: Connection, name: str, timeout: float | None = None) -> float | int:
    """The value of parameter `name` (an int for integer types); `ParamError` if unknown."""
    return param_value(_read(conn, name, timeout), _cast(conn))


def param_set(conn: Connection, name: str, value: float, int32: bool | None = None,
              timeout: float | None = None) -> float | int:
    """Sets `name` to `value` and checks the echo; returns the echoed value. `int32`: send as
    INT32 (True), REAL32 (False), or as the autopilot declares the parameter (None: its type is
    read first unless a PARAM_VALUE already told it). `ParamError` when the autopilot keeps
    another value (a refusal, with its reason) or does not know the name."""
    timeout = link_state(conn).timeout if timeout is None else timeout
    cast = _cast(conn)
    declared = link_state(conn).param_types.get(name)
    if declared is None and (int32 is None or (int32 and cast)):
        declared = _read(conn, name, timeout).param_type
    if int32 is None:
        int32 = declared in INTEGER_TYPES
    if int32:
        if int(value) != value:
            raise ParamError(f"{name}: {value} is not an integer")
        wanted: float | int = int(value)
        if cast:
            raw, ptype = float(wanted), declared if declared in INTEGER_TYPES else mavlink.MAV_PARAM_TYPE_INT32
        else:
            raw, ptype = int32_bits(int(value)), mavlink.MAV_PARAM_TYPE_INT32
    else:
        wanted = raw = as_float32(float(value))
        ptype = mavlink.MAV_PARAM_TYPE_REAL32
    start = time.monotonic()

    def send() -> None:
        conn.mav.param_set_send(conn.target_system, conn.target_component, name.encode(), raw, ptype)

    got = param_value(_param_reply(conn, name, start, timeout, send), cast)
    if got != wanted:
        reason = recent_text(conn, start, name)
        if reason is None:
            try:
                text = wait(conn, "STATUSTEXT", lambda m: name in m.text, timeout=0.5)
                reason = text.text
                keep(conn, text)
            except LinkTimeout:
                pass
        raise ParamError(f"{name} = {value} refused: the autopilot kept {got}" + (f" ({reason})" if reason else ""))
    return got


#: Silence after which `param_list` asks again for what is missing [s] (QGroundControl waits 1 s).
LIST_GAP_S = 1.0


def param_list(conn: Connection, timeout: float | None = None) -> dict[str, float | int]:
    """Every parameter, as QGroundControl reads them: PARAM_REQUEST_LIST, then after
    `LIST_GAP_S` of silence PARAM_REQUEST_READ by index for each one still missing (a lossy link
    loses some), until all `param_count` arrived. `ParamError` after `timeout` [s] without any."""
    timeout = link_state(conn).timeout if timeout is None else timeout
    cast = _cast(conn)
    values: dict[int, tuple[str, float | int]] = {}
    count: int | None = None
    conn.mav.param_request_list_send(conn.target_system, conn.target_component)
    heard = asked = time.monotonic()
    while count is None or len(values) < count:
        if time.monotonic() - heard > timeout:
            have = f"{len(values)} of {count}" if count is not None else "none"
            raise ParamError(f"parameter list: {have} after {timeout:g} s of silence")
        m = recv(conn, 0.1)
        if m is not None and m.get_type() == "PARAM_VALUE" and m.param_index != 65535:
            count = m.param_count
            values[m.param_index] = (m.param_id, param_value(m, cast))
            heard = time.monotonic()
            continue
        if m is not None:
            keep(conn, m)
        quiet = time.monotonic() - max(heard, asked)
        if count is None and quiet > LIST_GAP_S:
            # The request or every answer was lost: ask again.
            conn.mav.param_request_list_send(conn.target_system, conn.target_component)
            asked = time.monotonic()
        elif count is not None and quiet > LIST_GAP_S:
            # Ten at a time, as QGroundControl does; again 0.3 s later while they stay missing.
            for index in sorted(set(range(count)) - set(values))[:10]:
                conn.mav.param_request_read_send(conn.target_system, conn.target_component, b"", index)
            asked = time.monotonic() - LIST_GAP_S + 0.3
    return dict(values.values())
