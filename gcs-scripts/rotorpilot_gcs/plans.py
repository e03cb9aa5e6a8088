"""Plan files → `MissionItem` lists: rotorpilot's own JSON plan (metres from home), QGroundControl's
``.plan`` (mission, geofence, rally points) and the QGC WPL 110 text format (MAVProxy, Mission
Planner, QGC's legacy export). Bad files raise `UsageError` naming the file and the field."""
from __future__ import annotations

import json
import math
import pathlib
from dataclasses import dataclass, field
from typing import Any

from ._mav import mavlink
from .errors import UsageError
from .geo import offset_to_global
from .missions import MissionItem, nav_land, nav_return_to_launch, nav_takeoff, nav_waypoint

#: Frames whose x/y are latitude/longitude (MISSION_ITEM_INT carries them as degE7).
GLOBAL_FRAMES = frozenset({0, 3, 5, 6, 10, 11})
#: MAV_FRAME_MISSION: x/y are the command's params 5 and 6 as integers.
MISSION_FRAME = 2
#: QGC's fence and rally items: vertex/circle commands in MAV_FRAME_GLOBAL, rally points in
#: GLOBAL_RELATIVE_ALT.
FENCE_POLYGON_INCLUSION, FENCE_POLYGON_EXCLUSION = 5001, 5002
FENCE_CIRCLE_INCLUSION, FENCE_CIRCLE_EXCLUSION = 5003, 5004
RALLY_POINT = 5100
MAX_SPEED_M_S = 30.0


def _read_json(path: str | pathlib.Path) -> Any:
    try:
        return json.loads(pathlib.Path(path).read_text())
    except OSError as e:
        raise UsageError(f"{path}: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise UsageError(f"{path}: invalid JSON: {e}") from None


def _number(obj: dict[str, Any], key: str, where: str, required: bool = True, default: float | None = None,
            minimum: float | None = None, positive: bool = False) -> float | None:
    if key not in obj:
        if required:
            raise UsageError(f"{where}: missing field \"{key}\"")
        return default
    v = obj[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise UsageError(f"{where}: field \"{key}\" must be a number, not {json.dumps(v)}")
    if positive and v <= 0:
        raise UsageError(f"{where}: field \"{key}\" must be > 0, not {v}")
    if minimum is not None and v < minimum:
        raise UsageError(f"{where}: field \"{key}\" must be >= {minimum}, not {v}")
    return float(v)


def load_plan(path: str | pathlib.Path) -> dict[str, Any]:
    """rotorpilot's JSON plan, validated (see ``gcs-scripts/plans/square.json``)::

        {"takeoff_alt": 3,          required, > 0 [m above home]
         "speed": 5,                optional: DO_CHANGE_SPEED [m/s] after the take-off
         "waypoints": [{"north": 5, "east": 0, "alt": 3, "hold": 0}, ...],  [m, m, m, s]
         "rtl": true,               optional (default true); false: land at the last waypoint
         "rtl_alt": 5}              optional: RTL_RETURN_ALT [m] to set before the upload
    """
    plan = _read_json(path)
    if not isinstance(plan, dict):
        raise UsageError(f"{path}: the plan must be a JSON object")
    known = {"takeoff_alt", "speed", "waypoints", "rtl", "rtl_alt"}
    for key in plan:
        if key not in known:
            raise UsageError(f"{path}: unknown field \"{key}\" (known: {', '.join(sorted(known))})")
    where = str(path)
    out: dict[str, Any] = {
        "takeoff_alt": _number(plan, "takeoff_alt", where, positive=True),
        "speed": _number(plan, "speed", where, required=False, positive=True),
        "rtl_alt": _number(plan, "rtl_alt", where, required=False, positive=True),
    }
    if out["speed"] is not None and out["speed"] > MAX_SPEED_M_S:
        raise UsageError(f"{path}: field \"speed\" must be <= {MAX_SPEED_M_S:g} m/s")
    rtl = plan.get("rtl", True)
    if not isinstance(rtl, bool):
        raise UsageError(f"{path}: field \"rtl\" must be true or false")
    out["rtl"] = rtl
    if "waypoints" not in plan:
        raise UsageError(f"{path}: missing field \"waypoints\"")
    wps = plan["waypoints"]
    if not isinstance(wps, list) or not wps:
        raise UsageError(f"{path}: field \"waypoints\" must be a non-empty list")
    out["waypoints"] = []
    for i, wp in enumerate(wps):
        where = f"{path}: waypoints[{i}]"
        if not isinstance(wp, dict):
            raise UsageError(f"{where}: must be an object")
        for key in wp:
            if key not in ("north", "east", "alt", "hold"):
                raise UsageError(f"{where}: unknown field \"{key}\"")
        out["waypoints"].append({
            "north": _number(wp, "north", where),
            "east": _number(wp, "east", where),
            "alt": _number(wp, "alt", where, positive=True),
            "hold": _number(wp, "hold", where, required=False, default=0.0, minimum=0),
        })
    return out


def plan_items(plan: dict[str, Any], home_lat: float, home_lon: float) -> list[MissionItem]:
    """The mission items of a `load_plan` plan for a vehicle whose home is at (`home_lat`,
    `home_lon`) [deg], in GLOBAL_RELATIVE_ALT_INT: take-off above home, DO_CHANGE_SPEED, the
    waypoints, then RETURN_TO_LAUNCH or a landing at the last waypoint."""
    lat0, lon0 = offset_to_global(home_lat, home_lon, 0.0, 0.0)
    items = [nav_takeoff(lat0, lon0, plan["takeoff_alt"])]
    if plan["speed"] is not None:
        items.append(MissionItem(mavlink.MAV_CMD_DO_CHANGE_SPEED, param1=1, param2=plan["speed"], param3=-1,
                                 param4=math.nan, description=f"speed {plan['speed']:g} m/s"))
    for i, wp in enumerate(plan["waypoints"], 1):
        lat, lon = offset_to_global(home_lat, home_lon, wp["north"], wp["east"])
        item = nav_waypoint(lat, lon, wp["alt"], wp["hold"])
        item.description = f"waypoint {i}: north {wp['north']:g} east {wp['east']:g} alt {wp['alt']:g}"
        items.append(item)
    if plan["rtl"]:
        items.append(nav_return_to_launch())
    else:
        last = items[-1]
        items.append(nav_land(last.x, last.y))
        items[-1].description = "land at the last waypoint"
    return items


def _xy(frame: int, x: float, y: float) -> tuple[int, int]:
    """MISSION_ITEM_INT's x/y of params 5 and 6 in `frame`: degE7 in the global frames, the
    integer in MAV_FRAME_MISSION, metres × 1e4 in the local ones."""
    if frame in GLOBAL_FRAMES:
        return round(x * 1e7), round(y * 1e7)
    if frame == MISSION_FRAME:
        return round(x), round(y)
    return round(x * 1e4), round(y * 1e4)


def _param(v: Any, where: str) -> float:
    if v is None:
        return math.nan
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise UsageError(f"{where}: must be a number or null, not {json.dumps(v)}")
    return float(v)


@dataclass
class QgcPlan:
    """What a QGroundControl ``.plan`` holds: the mission's items, the geofence's and the rally
    points' (each uploaded with its MAV_MISSION_TYPE) and the planned home (lat, lon, alt)."""

    mission: list[MissionItem] = field(default_factory=list)
    fence: list[MissionItem] = field(default_factory=list)
    rally: list[MissionItem] = field(default_factory=list)
    home: tuple[float, float, float] | None = None


def qgc_plan_items(plan: dict[str, Any], where: str = "plan") -> QgcPlan:
    """The items of a QGC ``.plan`` already read as JSON. Mission items are its SimpleItems as
    they are (frame, params, autoContinue; null params NaN); fence items are QGC's
    GeoFenceManager's: each polygon's vertices (param1 the vertex count), then each circle
    (param1 the radius), in MAV_FRAME_GLOBAL; rally items are NAV_RALLY_POINT in
    GLOBAL_RELATIVE_ALT. Complex items (surveys, scans) are refused."""
    if not isinstance(plan, dict) or plan.get("fileType") != "Plan":
        raise UsageError(f"{where}: not a QGroundControl plan (no \"fileType\": \"Plan\")")
    out = QgcPlan()
    mission = plan.get("mission", {})
    home = mission.get("plannedHomePosition")
    if isinstance(home, list) and len(home) == 3 and all(isinstance(v, (int, float)) for v in home):
        out.home = (float(home[0]), float(home[1]), float(home[2]))
    for i, it in enumerate(mission.get("items", [])):
        at = f"{where}: mission.items[{i}]"
        if not isinstance(it, dict) or it.get("type") != "SimpleItem":
            kind = it.get("complexItemType", it.get("type")) if isinstance(it, dict) else type(it).__name__
            raise UsageError(f"{at}: only SimpleItems are supported, not {kind}")
        params = it.get("params")
        if not isinstance(params, list) or len(params) != 7:
            raise UsageError(f"{at}: field \"params\" must be a list of 7 numbers")
        p = [_param(v, f"{at}.params[{k}]") for k, v in enumerate(params)]
        frame, command = it.get("frame"), it.get("command")
        if not isinstance(frame, int) or not isinstance(command, int):
            raise UsageError(f"{at}: fields \"command\" and \"frame\" must be integers")
        x, y = _xy(frame, 0.0 if math.isnan(p[4]) else p[4], 0.0 if math.isnan(p[5]) else p[5])
        out.mission.append(MissionItem(command, x, y, 0.0 if math.isnan(p[6]) else p[6], frame, p[0], p[1], p[2], p[3],
                                       autocontinue=int(bool(it.get("autoContinue", True)))))
    fence = plan.get("geoFence", {})
    for k, poly in enumerate(fence.get("polygons", [])):
        vertices = poly.get("polygon", [])
        cmd = FENCE_POLYGON_INCLUSION if poly.get("inclusion", True) else FENCE_POLYGON_EXCLUSION
        for lat, lon in vertices:
            x, y = _xy(0, lat, lon)
            out.fence.append(MissionItem(cmd, x, y, 0.0, mavlink.MAV_FRAME_GLOBAL, float(len(vertices)),
                                         autocontinue=0, description=f"fence polygon {k}"))
    for k, c in enumerate(fence.get("circles", [])):
        lat, lon = c["circle"]["center"]
        cmd = FENCE_CIRCLE_INCLUSION if c.get("inclusion", True) else FENCE_CIRCLE_EXCLUSION
        x, y = _xy(0, lat, lon)
        out.fence.append(MissionItem(cmd, x, y, 0.0, mavlink.MAV_FRAME_GLOBAL, float(c["circle"]["radius"]),
                                     autocontinue=0, description=f"fence circle {k}"))
    for lat, lon, alt in plan.get("rallyPoints", {}).get("points", []):
        x, y = _xy(3, lat, lon)
        out.rally.append(MissionItem(RALLY_POINT, x, y, float(alt), mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT,
                                     autocontinue=0))
    return out


def load_qgc_plan(path: str | pathlib.Path) -> QgcPlan:
    """A QGroundControl ``.plan`` file's items (see `qgc_plan_items`)."""
    plan = _read_json(path)
    try:
        return qgc_plan_items(plan, str(path))
    except (KeyError, TypeError, ValueError) as e:
        raise UsageError(f"{path}: malformed plan ({type(e).__name__}: {e})") from None


def load_wpl(path: str | pathlib.Path, skip_home: bool = False) -> list[MissionItem]:
    """The items of a QGC WPL 110 file: a ``QGC WPL 110`` line, then per item ``INDEX CURRENT
    FRAME COMMAND P1 P2 P3 P4 X/LAT Y/LON Z/ALT AUTOCONTINUE`` (tabs or spaces). `skip_home`
    drops item 0, the home position ArduPilot's and MAVProxy's mission files start with."""
    try:
        lines = pathlib.Path(path).read_text().splitlines()
    except OSError as e:
        raise UsageError(f"{path}: {e.strerror}") from None
    if not lines or lines[0].split() != ["QGC", "WPL", "110"]:
        raise UsageError(f"{path}:1: not a QGC WPL 110 file (first line {lines[0]!r})" if lines
                         else f"{path}: empty file")
    items: list[MissionItem] = []
    for number, line in enumerate(lines[1:], 2):
        fields = line.split()
        if not fields:
            continue
        if len(fields) != 12:
            raise UsageError(f"{path}:{number}: {len(fields)} fields, not 12")
        try:
            index, _current, frame, command = (int(v) for v in fields[:4])
            p = [float(v) for v in fields[4:11]]
            autocontinue = int(fields[11])
        except ValueError as e:
            raise UsageError(f"{path}:{number}: {e}") from None
        if index != len(items):
            raise UsageError(f"{path}:{number}: item index {index}, expected {len(items)}")
        x, y = _xy(frame, p[4], p[5])
        items.append(MissionItem(command, x, y, p[6], frame, p[0], p[1], p[2], p[3], autocontinue=autocontinue))
    return items[1:] if skip_home else items
