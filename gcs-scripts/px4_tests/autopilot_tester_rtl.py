"""PX4's AutopilotTesterRtl (PX4-Autopilot test/mavsdk_tests/autopilot_tester_rtl.cpp/.h): RTL
parameters, rally points given in metres from home, a QGC plan's mission and geofence moved to
where the vehicle stands, and a breach monitor on the ground-truth track (an exclusion shape
entered or an inclusion shape left is a breach, latched with where it happened)."""
from __future__ import annotations

import dataclasses
import math
import warnings

from .autopilot_tester import finite, log, outcome, value_of
from .autopilot_tester_raw import MAV_FRAME_GLOBAL_RELATIVE_ALT, AutopilotTesterRaw
from .checks import check, require
from .geometry import CoordinateTransformation

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.mission_raw import MissionItem as RawItem

MAV_CMD_NAV_RALLY_POINT, MAV_MISSION_TYPE_RALLY = 5100, 2
POLYGON_INCLUSION, POLYGON_EXCLUSION, CIRCLE_INCLUSION, CIRCLE_EXCLUSION = 5001, 5002, 5003, 5004
#: MAV_FRAMEs whose x/y are latitude/longitude (others carry plain parameters there).
GLOBAL_FRAMES = {0, 3, 5, 6, 10, 11}


@dataclasses.dataclass
class Shape:
    command: int
    vertices: list = dataclasses.field(default_factory=list)  # polygons: (north, east) [m]
    centre: tuple = (0.0, 0.0)
    radius_m: float = 0.0

    def breached_at(self, north: float, east: float) -> bool:
        if self.command in (POLYGON_INCLUSION, POLYGON_EXCLUSION):
            if len(self.vertices) < 3:
                return False
            inside = point_in_polygon(north, east, self.vertices)
            return inside if self.command == POLYGON_EXCLUSION else not inside
        d = math.hypot(north - self.centre[0], east - self.centre[1])
        return d < self.radius_m if self.command == CIRCLE_EXCLUSION else d > self.radius_m


def point_in_polygon(north: float, east: float, polygon) -> bool:
    """Even-odd rule on a ray along north."""
    inside, j = False, len(polygon) - 1
    for i, (ni, ei) in enumerate(polygon):
        nj, ej = polygon[j]
        if (ei > east) != (ej > east) and north < (nj - ni) * (east - ei) / (ej - ei) + ni:
            inside = not inside
        j = i
    return inside


class AutopilotTesterRtl(AutopilotTesterRaw):
    def __init__(self) -> None:
        super().__init__()
        self.rally_items: list = []
        self.local_rally_points: list = []
        self.shapes: list[Shape] = []
        self.breach = None
        self._monitor = None

    async def set_rtl_type(self, rtl_type: int) -> None:
        await self.set_param_int("RTL_TYPE", rtl_type)

    async def set_rtl_appr_force(self, value: int) -> None:
        await self.set_param_int("RTL_APPR_FORCE", value)

    def add_local_rally_point(self, north_m: float, east_m: float) -> None:
        self.local_rally_points.append((north_m, east_m))
        lat, lon = self.get_coordinate_transformation().global_from_local(north_m, east_m)
        first = not self.rally_items
        self.rally_items.append(RawItem(len(self.rally_items), MAV_FRAME_GLOBAL_RELATIVE_ALT, MAV_CMD_NAV_RALLY_POINT,
                                        1 if first else 0, 0, 0.0, 0.0, 0.0, 0.0, int(lat * 1e7), int(lon * 1e7),
                                        0.0, MAV_MISSION_TYPE_RALLY))

    async def upload_rally_points(self) -> None:
        result = await outcome(self.drone.mission_raw.upload_rally_points(self.rally_items))
        require(result == "SUCCESS", "upload_rally_points() == Success", result)

    def check_rally_point_within(self, radius_m: float) -> None:
        home = self.get_home()
        ct = CoordinateTransformation(home[0], home[1])
        distances = [self._truth_distance((*ct.global_from_local(n, e), 0.0)) for n, e in self.local_rally_points]
        check(any(d < radius_m for d in distances), f"ground truth within {radius_m} m of a rally point", distances)

    async def load_qgc_mission_and_geofence_here(self, plan_path: str) -> None:
        result, data = await value_of(self.drone.mission_raw.import_qgroundcontrol_mission(plan_path))
        require(result == "SUCCESS", f"import_qgroundcontrol_mission({plan_path}) == Success", result)
        require(bool(data.mission_items), "the plan has mission items", 0)
        here = self.latest("position")
        lat, lon = (here.latitude_deg, here.longitude_deg) if here is not None else (math.nan, math.nan)
        require(finite(lat, lon), "global position finite to move the plan here", (lat, lon))
        dx, dy = data.mission_items[0].x - int(1e7 * lat), data.mission_items[0].y - int(1e7 * lon)
        for item in [*data.mission_items, *data.geofence_items]:
            if item.frame in GLOBAL_FRAMES:
                item.x -= dx
                item.y -= dy
        result = await outcome(self.drone.mission_raw.upload_mission(data.mission_items))
        require(result == "SUCCESS", "mission_raw upload_mission() == Success", result)
        self.shapes = []
        if data.geofence_items:
            result = await outcome(self.drone.mission_raw.upload_geofence(data.geofence_items))
            require(result == "SUCCESS", "upload_geofence() == Success", result)
            self.shapes = self._shapes(data.geofence_items)
        await self.sleep_for(1)

    def _shapes(self, items) -> list[Shape]:
        ct, shapes, polygon, size = self.get_coordinate_transformation(), [], None, 0
        for item in items:
            local = ct.local_from_global(item.x / 1e7, item.y / 1e7)
            if item.command in (POLYGON_INCLUSION, POLYGON_EXCLUSION):
                if polygon is None or polygon.command != item.command or len(polygon.vertices) >= size:
                    polygon = Shape(item.command)
                    shapes.append(polygon)
                    size = int(item.param1)
                polygon.vertices.append(local)
            elif item.command in (CIRCLE_INCLUSION, CIRCLE_EXCLUSION):
                polygon = None
                shapes.append(Shape(item.command, centre=local, radius_m=float(item.param1)))
        return shapes

    def start_monitoring_geofence_breach(self) -> None:
        require(bool(self.shapes), "geofence shapes loaded before monitoring", 0)
        ct = self.get_coordinate_transformation()

        async def monitor():
            async for gt in self.drone.telemetry.ground_truth():
                if not finite(gt.latitude_deg, gt.longitude_deg) or self.breach is not None:
                    continue
                north, east = ct.local_from_global(gt.latitude_deg, gt.longitude_deg)
                for i, shape in enumerate(self.shapes):
                    if shape.breached_at(north, east):
                        self.breach = f"shape #{i} at NED ({north:.1f}, {east:.1f})"
                        log(f"GEOFENCE BREACH {self.breach}")
                        break
        self._monitor = self.background(monitor())

    def check_no_geofence_breach(self) -> None:
        if self._monitor is not None:
            self._monitor.cancel()
        check(self.breach is None, "no geofence breach on the ground-truth track", self.breach)
