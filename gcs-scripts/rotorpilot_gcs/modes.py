"""PX4's flight modes as HEARTBEAT.custom_mode carries them: main mode in bits 16–23, sub mode in
bits 24–31 (PX4's ``px4_custom_mode``), named as QGroundControl and PX4 name them."""
from __future__ import annotations

from typing import Union

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
    """The name of a HEARTBEAT custom_mode value (``"mode 9/0"`` for one PX4 does not name)."""
    main, sub = mode_of(value)
    return MODE_NAMES.get((main, sub), f"mode {main}/{sub}")
