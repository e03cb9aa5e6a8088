"""Flight modes as HEARTBEAT.custom_mode carries them, for both personalities of a vehicle.

PX4's: main mode in bits 16–23, sub mode in bits 24–31 (PX4's ``px4_custom_mode``), named as
QGroundControl and PX4 name them (``"AUTO.MISSION"``). ArduCopter's: the Copter mode number
itself (``GUIDED`` 4), named as ArduCopter's ``mode.h`` and pymavlink name them. Which table a
vehicle's modes come from is its personality, which its HEARTBEAT tells
(``autopilot`` MAV_AUTOPILOT_ARDUPILOTMEGA 3: ArduCopter; any other: PX4): `vehicle_custom_mode`
and `vehicle_mode_name` take it. A name of the other table is refused (`ModeError`, naming the mode
and the personality): no PX4 name is mapped onto a Copter mode or the reverse, as the modes that
look alike fly differently (PX4's AUTO.LOITER holds, Copter's LOITER takes the sticks).
"""
from __future__ import annotations

from typing import Union

from .errors import ModeError

#: (main, sub) of each PX4 mode by its name.
PX4_MODES: dict[str, tuple[int, int]] = {
    "MANUAL": (1, 0),
    "ALTCTL": (2, 0),
    "POSCTL": (3, 0),
    "POSCTL.ORBIT": (3, 1),
    "AUTO.READY": (4, 1),
    "AUTO.TAKEOFF": (4, 2),
    "AUTO.LOITER": (4, 3),
    "AUTO.MISSION": (4, 4),
    "AUTO.RTL": (4, 5),
    "AUTO.LAND": (4, 6),
    "AUTO.FOLLOW_TARGET": (4, 8),
    "GOTO": (4, 21),  # PX4's multicopter Goto (PX4_CUSTOM_SUB_MODE_GOTO), entered by DO_REPOSITION
    "OFFBOARD": (6, 0),
    "STABILIZED": (7, 0),
    "ACRO": (8, 0),
}
#: Mode names by (main, sub).
MODE_NAMES: dict[tuple[int, int], str] = {v: k for k, v in PX4_MODES.items()}

POSCTL = PX4_MODES["POSCTL"]
AUTO_TAKEOFF = PX4_MODES["AUTO.TAKEOFF"]
AUTO_LOITER = PX4_MODES["AUTO.LOITER"]
AUTO_MISSION = PX4_MODES["AUTO.MISSION"]
AUTO_RTL = PX4_MODES["AUTO.RTL"]
AUTO_LAND = PX4_MODES["AUTO.LAND"]
OFFBOARD = PX4_MODES["OFFBOARD"]

#: A mode: its name (``"AUTO.RTL"``, any case) or (main, sub).
Mode = Union[str, tuple[int, int]]


def parse_mode(mode: Mode) -> tuple[int, int]:
    """(main, sub) of `mode`; ValueError for an unknown name."""
    if isinstance(mode, str):
        try:
            return PX4_MODES[mode.strip().upper()]
        except KeyError:
            raise ValueError(f"unknown PX4 mode {mode!r} (known: {', '.join(PX4_MODES)})") from None
    main, sub = mode
    return int(main), int(sub)


def custom_mode(mode: Mode | int, sub: int = 0) -> int:
    """HEARTBEAT.custom_mode of `mode` (a name or (main, sub)), or of main mode `mode` (an int)
    and sub mode `sub`."""
    if isinstance(mode, int):
        main = mode
    else:
        main, sub = parse_mode(mode)
    return (main << 16) | (sub << 24)


def mode_of(value: int) -> tuple[int, int]:
    """(main, sub) of a HEARTBEAT custom_mode value."""
    return (value >> 16) & 0xFF, (value >> 24) & 0xFF


def mode_name(value: int) -> str:
    """The name of a PX4 HEARTBEAT custom_mode value (``"mode 9/0"`` for one PX4 does not name)."""
    main, sub = mode_of(value)
    return MODE_NAMES.get((main, sub), f"mode {main}/{sub}")


#: The personalities, as `Autopilot.start(autopilot=...)` names them.
PX4, ARDUPILOT = "px4", "ardupilot"
#: HEARTBEAT.autopilot of an ArduPilot vehicle (MAV_AUTOPILOT_ARDUPILOTMEGA).
MAV_AUTOPILOT_ARDUPILOTMEGA = 3
#: How errors and reports name each personality.
PERSONALITY_NAMES = {PX4: "PX4", ARDUPILOT: "ArduCopter"}

#: ArduCopter's flight modes by name: HEARTBEAT.custom_mode is the number (``mode.h``'s
#: ``Mode::Number``). All of Copter's are named; the vehicle refuses those it does not fly
#: (docs/ardupilot.md §2: "Mode change to FLIP failed: not emulated").
COPTER_MODES: dict[str, int] = {
    "STABILIZE": 0,
    "ACRO": 1,
    "ALT_HOLD": 2,
    "AUTO": 3,
    "GUIDED": 4,
    "LOITER": 5,
    "RTL": 6,
    "CIRCLE": 7,
    "LAND": 9,
    "DRIFT": 11,
    "SPORT": 13,
    "FLIP": 14,
    "AUTOTUNE": 15,
    "POSHOLD": 16,
    "BRAKE": 17,
    "THROW": 18,
    "AVOID_ADSB": 19,
    "GUIDED_NOGPS": 20,
    "SMART_RTL": 21,
    "FLOWHOLD": 22,
    "FOLLOW": 23,
    "ZIGZAG": 24,
    "SYSTEMID": 25,
    "AUTOROTATE": 26,
    "AUTO_RTL": 27,
    "TURTLE": 28,
}
#: Copter mode names by number.
COPTER_MODE_NAMES: dict[int, str] = {v: k for k, v in COPTER_MODES.items()}


#: What a script asks of a vehicle whatever its personality: to take the ground station's position
#: setpoints, to hold where it is, to fly the uploaded mission.
SETPOINTS, HOLD, MISSION = "setpoints", "hold", "mission"
#: The mode each personality does each of them in, by its own name (the modes themselves are not
#: mapped onto each other: PX4's AUTO.LOITER holds with no pilot, Copter's LOITER with the sticks
#: centred, as its receiver rests in the air).
ROLE_MODES: dict[str, dict[str, str]] = {
    PX4: {SETPOINTS: "OFFBOARD", HOLD: "AUTO.LOITER", MISSION: "AUTO.MISSION"},
    ARDUPILOT: {SETPOINTS: "GUIDED", HOLD: "LOITER", MISSION: "AUTO"},
}


def mode_for(personality: str, role: str) -> str:
    """The name of the mode a vehicle of `personality` does `role` in (`SETPOINTS`, `HOLD`,
    `MISSION`); `ModeError` for another role."""
    modes = ROLE_MODES[ARDUPILOT if personality == ARDUPILOT else PX4]
    if role not in modes:
        raise ModeError(f"unknown role {role!r} (known: {', '.join(modes)})")
    return modes[role]


def personality_of(autopilot: int) -> str:
    """The personality a HEARTBEAT's ``autopilot`` field tells: `ARDUPILOT` for
    MAV_AUTOPILOT_ARDUPILOTMEGA (3), else `PX4`."""
    return ARDUPILOT if autopilot == MAV_AUTOPILOT_ARDUPILOTMEGA else PX4


def _names(table: dict[str, int] | dict[str, tuple[int, int]]) -> str:
    return ", ".join(table)


def copter_custom_mode(mode: Mode | int, sub: int | None = None) -> int:
    """HEARTBEAT.custom_mode of an ArduCopter mode: a Copter name (``"GUIDED"``, any case) or
    number. `ModeError` for a PX4 name, a PX4 (main, sub) pair or an unknown name."""
    if isinstance(mode, bool) or (isinstance(mode, int) and sub):
        raise ModeError(f"ArduCopter modes have no sub mode: {mode!r}, {sub!r}")
    if isinstance(mode, int):
        return mode
    if not isinstance(mode, str):
        raise ModeError(f"{mode!r} is a PX4 (main, sub) mode; this vehicle is ArduCopter, whose modes are named "
                        f"({_names(COPTER_MODES)}) or numbered")
    name = mode.strip().upper()
    if name in COPTER_MODES:
        return COPTER_MODES[name]
    if name in PX4_MODES:
        raise ModeError(f"{mode!r} is a PX4 mode; this vehicle is ArduCopter, whose modes are {_names(COPTER_MODES)} "
                        "(AUTO flies the mission, RTL returns, LAND lands, GUIDED takes targets)")
    raise ModeError(f"unknown ArduCopter mode {mode!r} (known: {_names(COPTER_MODES)})")


def px4_custom_mode(mode: Mode | int, sub: int | None = None) -> int:
    """`custom_mode` with `ModeError` naming the personality for an ArduCopter name given to PX4."""
    if isinstance(mode, str):
        name = mode.strip().upper()
        if name not in PX4_MODES and name in COPTER_MODES:
            raise ModeError(f"{mode!r} is an ArduCopter mode; this vehicle is PX4, whose modes are "
                            f"{_names(PX4_MODES)}")
    return custom_mode(mode, sub or 0)


def vehicle_custom_mode(personality: str, mode: Mode | int, sub: int | None = None) -> int:
    """HEARTBEAT.custom_mode of `mode` on a vehicle of `personality` (`PX4`: a name, (main, sub),
    or the main mode as an int and `sub`; `ARDUPILOT`: a Copter name or number)."""
    return copter_custom_mode(mode, sub) if personality == ARDUPILOT else px4_custom_mode(mode, sub)


def vehicle_mode_name(personality: str, value: int) -> str:
    """The name of HEARTBEAT.custom_mode `value` on a vehicle of `personality` (``"mode 8"`` for
    a Copter number Copter does not name)."""
    if personality == ARDUPILOT:
        return COPTER_MODE_NAMES.get(value, f"mode {value}")
    return mode_name(value)
