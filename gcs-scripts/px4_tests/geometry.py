"""The geometry the tester needs: MAVSDK's CoordinateTransformation (an azimuthal equidistant
projection about a reference point on a sphere of radius 6371 km, as MAVSDK and PX4 project local
positions) and the small vector helpers of PX4's math_helpers.h, re-derived."""
from __future__ import annotations

import math

EARTH_RADIUS_M = 6371000.0


class CoordinateTransformation:
    """Local north/east metres about a reference (latitude, longitude) [deg] and back."""

    def __init__(self, ref_lat_deg: float, ref_lon_deg: float) -> None:
        self.lat0 = math.radians(ref_lat_deg)
        self.lon0 = math.radians(ref_lon_deg)

    def local_from_global(self, lat_deg: float, lon_deg: float) -> tuple[float, float]:
        lat, lon = math.radians(lat_deg), math.radians(lon_deg)
        cos_dlon = math.cos(lon - self.lon0)
        arg = math.sin(self.lat0) * math.sin(lat) + math.cos(self.lat0) * math.cos(lat) * cos_dlon
        c = math.acos(max(-1.0, min(1.0, arg)))
        k = 1.0 if abs(c) < 1e-12 else c / math.sin(c)
        north = k * (math.cos(self.lat0) * math.sin(lat) - math.sin(self.lat0) * math.cos(lat) * cos_dlon)
        east = k * math.cos(lat) * math.sin(lon - self.lon0)
        return north * EARTH_RADIUS_M, east * EARTH_RADIUS_M

    def global_from_local(self, north_m: float, east_m: float) -> tuple[float, float]:
        x, y = north_m / EARTH_RADIUS_M, east_m / EARTH_RADIUS_M
        c = math.hypot(x, y)
        if c < 1e-12:
            return math.degrees(self.lat0), math.degrees(self.lon0)
        sin_c, cos_c = math.sin(c), math.cos(c)
        lat = math.asin(cos_c * math.sin(self.lat0) + x * sin_c * math.cos(self.lat0) / c)
        lon = self.lon0 + math.atan2(y * sin_c, c * math.cos(self.lat0) * cos_c - x * math.sin(self.lat0) * sin_c)
        return math.degrees(lat), math.degrees(lon)


def diff(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def dot(a, b) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a) -> float:
    return math.sqrt(dot(a, a))


def point_to_line_distance(p, start, end) -> float:
    """Distance from `p` to the infinite line through `start` and `end` (a point when they coincide)."""
    d = diff(end, start)
    length = norm(d)
    u = [v / length for v in d] if length > 1e-6 else [0.0, 0.0, 0.0]
    t = dot(u, diff(p, start))
    closest = [start[i] + t * u[i] for i in range(3)]
    return norm(diff(closest, p))


def point_to_segment_distance(p, start, end) -> float:
    """Distance from `p` to the segment from `start` to `end`."""
    d = diff(end, start)
    length2 = dot(d, d)
    t = dot(diff(p, start), d) / length2 if length2 > 0 else 0.0
    t = max(0.0, min(1.0, t))
    return norm(diff([start[i] + t * d[i] for i in range(3)], p))
