"""Positions near home: metres north/east of a point ↔ latitude/longitude, by the
equirectangular approximation on a sphere of radius `EARTH_RADIUS_M` (good to millimetres over
the few hundred metres a test flies)."""
from __future__ import annotations

import math

#: Mean Earth radius [m].
EARTH_RADIUS_M = 6371000.0
#: `rotorpilot run`'s default home: latitude [deg], longitude [deg], altitude [m AMSL].
DEFAULT_HOME = (47.397742, 8.545594, 488.0)


def offset_to_global(lat_deg: float, lon_deg: float, north_m: float, east_m: float) -> tuple[int, int]:
    """(latitude, longitude) [degE7] of the point `north_m` / `east_m` metres from (`lat_deg`, `lon_deg`)."""
    lat = lat_deg + math.degrees(north_m / EARTH_RADIUS_M)
    lon = lon_deg + math.degrees(east_m / (EARTH_RADIUS_M * math.cos(math.radians(lat_deg))))
    return round(lat * 1e7), round(lon * 1e7)


def global_to_offset(origin_lat_deg: float, origin_lon_deg: float, lat_deg: float,
                     lon_deg: float) -> tuple[float, float]:
    """(north, east) [m] of (`lat_deg`, `lon_deg`) from the origin."""
    north = math.radians(lat_deg - origin_lat_deg) * EARTH_RADIUS_M
    east = math.radians(lon_deg - origin_lon_deg) * EARTH_RADIUS_M * math.cos(math.radians(origin_lat_deg))
    return north, east


def deg_e7_per_metre(lat_deg: float) -> tuple[float, float]:
    """degE7 of latitude per metre north, and of longitude per metre east at latitude `lat_deg`."""
    north = 1e7 / math.radians(1.0) / EARTH_RADIUS_M
    return north, north / math.cos(math.radians(lat_deg))
