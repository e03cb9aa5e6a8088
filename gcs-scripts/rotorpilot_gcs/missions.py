"""The mission protocol: upload, download and clear a plan (the mission, the geofence or the rally
points: MAV_MISSION_TYPE 0, 1, 2) as MISSION_ITEM_INT, as QGroundControl's plan managers do.

Every request the autopilot leaves unanswered is sent again every `RESEND_S` (the count, the
last item, a request for an item): the autopilot asks again for a lost item itself, but nothing
recovers a lost count or a lost last item otherwise.

The caller's list of mission items means the same items on both personalities. ArduCopter keeps
its home as item 0 of the mission (docs/ardupilot.md §6): to an ArduCopter vehicle the mission is
uploaded with home (`home_item`) inserted as item 0, and downloaded with item 0 stripped; a
DO_JUMP's target (param1, the caller's index from 0) is moved up by one on the way there and
down on the way back, and `wait_item_reached` takes the caller's index. Geofence and rally
plans have no home slot.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Iterable

from ._mav import mavlink
from .errors import LinkTimeout, MissionError
from .link import RESEND_S, Connection, Message, keep, link_state, personality, recent_text, recv, wait
from .modes import ARDUPILOT
from .names import enum_name
from .params import as_float32
from .telemetry import home_position

#: MAV_MISSION_TYPE: the mission, the geofence, the rally points, and all of them (clear only).
MISSION, FENCE, RALLY, ALL = 0, 1, 2, 255
NAN = float("nan")


@dataclass(eq=False)
class MissionItem:
    """One plan item as MISSION_ITEM_INT carries it. In the global frames `x`/`y` are latitude/
    longitude [degE7] and `z` the altitude [m] (above home in GLOBAL_RELATIVE_ALT_INT, the
    default). Items compare equal when every field is equal as the autopilot stores it (floats
    as float32, NaN equal to NaN); `description` is not compared."""

    command: int
    x: int = 0
    y: int = 0
    z: float = 0.0
    frame: int = mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
    param1: float = 0.0
    param2: float = 0.0
    param3: float = 0.0
    param4: float = 0.0
    autocontinue: int = 1
    description: str = field(default="", compare=False)

    def key(self) -> tuple[Any, ...]:
        """The compared fields (floats as float32, NaN as None)."""
        def f(v: float) -> float | None:
            return None if math.isnan(v) else as_float32(v)

        return (self.command, self.frame, self.x, self.y, f(self.z), f(self.param1), f(self.param2), f(self.param3),
                f(self.param4), self.autocontinue)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, MissionItem) and self.key() == other.key()

    def __hash__(self) -> int:
        return hash(self.key())


def nav_takeoff(lat_e7: int, lon_e7: int, alt_m: float) -> MissionItem:
    """NAV_TAKEOFF to `alt_m` [m above home] at the given place."""
    return MissionItem(mavlink.MAV_CMD_NAV_TAKEOFF, lat_e7, lon_e7, alt_m, param4=NAN,
                       description=f"take-off to {alt_m:g} m")


def nav_waypoint(lat_e7: int, lon_e7: int, alt_m: float, hold_s: float = 0.0) -> MissionItem:
    """NAV_WAYPOINT at `alt_m` [m above home], holding `hold_s` [s] there, heading unchanged."""
    return MissionItem(mavlink.MAV_CMD_NAV_WAYPOINT, lat_e7, lon_e7, alt_m, param1=hold_s, param4=NAN)


def nav_land(lat_e7: int, lon_e7: int) -> MissionItem:
    """NAV_LAND at the given place."""
    return MissionItem(mavlink.MAV_CMD_NAV_LAND, lat_e7, lon_e7, 0.0, param4=NAN)


def nav_return_to_launch() -> MissionItem:
    """NAV_RETURN_TO_LAUNCH (the mission's end: return, land, disarm)."""
    return MissionItem(mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, description="return to launch")


def home_item(lat_deg: float, lon_deg: float, alt_amsl_m: float) -> MissionItem:
    """ArduCopter's item 0, home: NAV_WAYPOINT in MAV_FRAME_GLOBAL at the AMSL altitude [m], as
    the vehicle reports it (stored as sent, never flown)."""
    return MissionItem(mavlink.MAV_CMD_NAV_WAYPOINT, round(lat_deg * 1e7), round(lon_deg * 1e7), alt_amsl_m,
                       mavlink.MAV_FRAME_GLOBAL, description="home (ArduCopter's item 0)")


def _jumps_moved(items: list[MissionItem], by: int) -> list[MissionItem]:
    """`items` with each DO_JUMP's target item (param1) moved by `by`."""
    return [replace(it, param1=it.param1 + by) if it.command == mavlink.MAV_CMD_DO_JUMP else it
            for it in items]


def home_slot(conn: Connection, mission_type: int = MISSION) -> int:
    """How many items the vehicle keeps before the caller's items of plan `mission_type`: 1 for an
    ArduCopter vehicle's mission (home), else 0. The vehicle's mission seqs (MISSION_CURRENT,
    MISSION_ITEM_REACHED) are the caller's indices + this."""
    return 1 if mission_type == MISSION and personality(conn) == ARDUPILOT else 0


def wait_item_reached(conn: Connection, index: int, timeout: float | None = None) -> Message:
    """The MISSION_ITEM_REACHED of the caller's mission item `index` (from 0, as uploaded; on
    ArduCopter its seq counts the home slot)."""
    seq = index + home_slot(conn)
    return wait(conn, "MISSION_ITEM_REACHED", lambda m: m.seq == seq, timeout, f"mission item {index} reached")


def item_from_message(m: Message) -> MissionItem:
    """The MissionItem a MISSION_ITEM_INT carries."""
    return MissionItem(m.command, m.x, m.y, m.z, m.frame, m.param1, m.param2, m.param3, m.param4, m.autocontinue)


def _exchange(conn: Connection, send: Callable[[], None], wanted: Callable[[Message], bool], timeout: float,
              what: str) -> Message:
    """Calls `send()` and again every `RESEND_S` while nothing `wanted` arrives; the first
    wanted message, `LinkTimeout` after `timeout` [s] of silence."""
    deadline = time.monotonic() + timeout
    send()
    resend = time.monotonic() + RESEND_S
    while (remaining := deadline - time.monotonic()) > 0:
        m = recv(conn, max(0.0, min(remaining, resend - time.monotonic())))
        if m is not None and wanted(m):
            return m
        if m is not None:
            keep(conn, m)
        if time.monotonic() >= resend:
            send()
            resend = time.monotonic() + RESEND_S
    raise LinkTimeout(f"timed out after {timeout:g} s waiting for {what}")


def _refused(conn: Connection, ack: Message, start: float, what: str) -> MissionError:
    reason = recent_text(conn, start)
    return MissionError(f"{what} refused: {enum_name('MAV_MISSION_RESULT', ack.type)}"
                        + (f" ({reason})" if reason else ""), ack.type)


def upload_mission(conn: Connection, items: Iterable[MissionItem], mission_type: int = MISSION,
                   timeout: float | None = None) -> Message:
    """Uploads `items` as plan `mission_type` (MISSION_COUNT, then one MISSION_ITEM_INT per
    request); returns the MISSION_ACK. `MissionError` (its `result` the MAV_MISSION_RESULT, with
    the autopilot's STATUSTEXT) unless ACCEPTED; a refused upload leaves the stored plan as it was.
    To an ArduCopter vehicle a non-empty mission goes with home inserted as item 0 (module
    description); an empty one is a count of 0."""
    items = list(items)
    timeout = link_state(conn).timeout if timeout is None else timeout
    if items and home_slot(conn, mission_type):
        items = [home_item(*home_position(conn, timeout))] + _jumps_moved(items, 1)
    start = time.monotonic()

    def send_count() -> None:
        conn.mav.mission_count_send(conn.target_system, conn.target_component, len(items), mission_type)

    def send_item(seq: int) -> Callable[[], None]:
        it = items[seq]

        def send() -> None:
            conn.mav.mission_item_int_send(conn.target_system, conn.target_component, seq, it.frame, it.command, 0,
                                           it.autocontinue, it.param1, it.param2, it.param3, it.param4, it.x, it.y,
                                           it.z, mission_type)
        return send

    def answer(m: Message) -> bool:
        return (m.get_type() in ("MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK")
                and m.mission_type == mission_type)

    send = send_count
    while True:
        m = _exchange(conn, send, answer, timeout, "MISSION_REQUEST_INT or MISSION_ACK")
        if m.get_type() == "MISSION_ACK":
            if m.type != mavlink.MAV_MISSION_ACCEPTED:
                raise _refused(conn, m, start, "upload")
            return m
        if m.seq >= len(items):
            raise MissionError(f"the autopilot asked for item {m.seq} of {len(items)}")
        send = send_item(m.seq)


def download_mission(conn: Connection, mission_type: int = MISSION, timeout: float | None = None) -> list[MissionItem]:
    """The stored plan `mission_type`, as QGroundControl downloads it (MISSION_REQUEST_LIST,
    MISSION_REQUEST_INT for each item, MISSION_ACK at the end); from an ArduCopter vehicle, the
    mission without its item 0, home (module description)."""
    timeout = link_state(conn).timeout if timeout is None else timeout
    skip = home_slot(conn, mission_type)
    target = (conn.target_system, conn.target_component)
    count = _exchange(conn, lambda: conn.mav.mission_request_list_send(*target, mission_type),
                      lambda m: m.get_type() == "MISSION_COUNT" and m.mission_type == mission_type, timeout,
                      "MISSION_COUNT")
    items = []
    for seq in range(count.count):
        def request(s: int = seq) -> None:
            conn.mav.mission_request_int_send(*target, s, mission_type)

        def answer(m: Message, s: int = seq) -> bool:
            return bool(m.get_type() == "MISSION_ITEM_INT" and m.seq == s and m.mission_type == mission_type)

        items.append(item_from_message(_exchange(conn, request, answer, timeout, f"MISSION_ITEM_INT {seq}")))
    conn.mav.mission_ack_send(*target, mavlink.MAV_MISSION_ACCEPTED, mission_type)
    return _jumps_moved(items[skip:], -skip) if skip else items


def clear_mission(conn: Connection, mission_type: int = MISSION, timeout: float | None = None) -> Message:
    """MISSION_CLEAR_ALL of plan `mission_type` (`ALL`: every plan); the MISSION_ACK, `MissionError`
    unless ACCEPTED."""
    timeout = link_state(conn).timeout if timeout is None else timeout
    start = time.monotonic()
    ack = _exchange(conn, lambda: conn.mav.mission_clear_all_send(conn.target_system, conn.target_component,
                                                                  mission_type),
                    lambda m: m.get_type() == "MISSION_ACK" and m.mission_type == mission_type, timeout, "MISSION_ACK")
    if ack.type != mavlink.MAV_MISSION_ACCEPTED:
        raise _refused(conn, ack, start, "clear")
    return ack
