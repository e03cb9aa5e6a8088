"""MAVLink commands (COMMAND_LONG) and their COMMAND_ACK; information requests (REQUEST_MESSAGE)."""
from __future__ import annotations

import time

from ._mav import mavlink
from .errors import CommandError, LinkTimeout
from .link import RESEND_S, Connection, Message, keep, latest, link_state, recent_text, recv, service, wait

NAN = float("nan")
#: The time a command's COMMAND_ACK has to come in [s] (MAVLink's command protocol).
ACK_TIMEOUT_S = 0.5


def _params(params: tuple[float | None, ...]) -> list[float]:
    if len(params) > 7:
        raise ValueError("COMMAND_LONG has seven parameters")
    return [NAN if v is None else float(v) for v in params] + [NAN] * (7 - len(params))


def _target(conn: Connection, target: tuple[int, int] | None) -> tuple[int, int]:
    return target if target is not None else (conn.target_system, conn.target_component)


def command(conn: Connection, cmd_id: int, *params: float | None, timeout: float | None = None,
            target: tuple[int, int] | None = None) -> Message:
    """COMMAND_LONG `cmd_id` with `params` (unset ones and None NaN) to the connection's target
    (or `target`, (system, component)); returns the COMMAND_ACK when ACCEPTED, else raises
    `CommandError` naming the command, the MAV_RESULT and the autopilot's STATUSTEXT about it.
    Sent again every `RESEND_S` (confirmation counting up) until answered: the autopilot
    answers repeats from its cache. IN_PROGRESS extends the wait."""
    p = _params(params)
    system, component = _target(conn, target)
    timeout = link_state(conn).timeout if timeout is None else timeout
    start = time.monotonic()
    deadline = start + timeout
    service(conn)
    sent = 0
    while True:
        if time.monotonic() >= deadline:
            raise CommandError(cmd_id, None, f"nothing within {timeout:g} s")
        conn.mav.command_long_send(system, component, cmd_id, min(sent, 255), *p)
        sent += 1
        resend = min(deadline, time.monotonic() + RESEND_S)
        while (remaining := resend - time.monotonic()) > 0:
            m = recv(conn, remaining)
            if m is None:
                continue
            if m.get_type() != "COMMAND_ACK" or m.command != cmd_id:
                keep(conn, m)
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
                    text = wait(conn, "STATUSTEXT", timeout=0.3)
                    reason = text.text
                    keep(conn, text)
                except LinkTimeout:
                    pass
            raise CommandError(cmd_id, m.result, reason)


def command_ack(conn: Connection, cmd_id: int, *params: float | None, timeout: float = ACK_TIMEOUT_S,
                target: tuple[int, int] | None = None) -> Message | None:
    """One COMMAND_LONG (not repeated); its COMMAND_ACK whatever the result, or None when none
    came within `timeout` [s]. For tests of the command protocol itself: `command` is the helper
    that retries and raises."""
    p = _params(params)
    system, component = _target(conn, target)
    conn.mav.command_long_send(system, component, cmd_id, 0, *p)
    deadline = time.monotonic() + timeout
    while (remaining := deadline - time.monotonic()) > 0:
        m = recv(conn, remaining)
        if m is None:
            continue
        if m.get_type() == "COMMAND_ACK" and m.command == cmd_id:
            return m
        keep(conn, m)
    return None


def request_message(conn: Connection, msg_id: int, kind: str, timeout: float | None = None) -> Message:
    """REQUEST_MESSAGE for message `msg_id`; returns the `kind` message that answers it. Asks
    again every `RESEND_S` while the ACK came but the message did not (it was lost)."""
    timeout = link_state(conn).timeout if timeout is None else timeout
    deadline = time.monotonic() + timeout
    while True:
        start = time.monotonic()
        command(conn, mavlink.MAV_CMD_REQUEST_MESSAGE, msg_id, timeout=max(deadline - start, 0.0))
        got = latest(conn, kind, since=start)
        if got is not None:
            return got
        remaining = deadline - time.monotonic()
        try:
            return wait(conn, kind, timeout=min(max(remaining, 0.0), RESEND_S))
        except LinkTimeout:
            if time.monotonic() >= deadline:
                raise LinkTimeout(f"timed out after {timeout:g} s waiting for {kind}") from None
