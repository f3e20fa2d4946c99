"""Flat-earth geometry of areas, enough to place maneuvers (areas span kilometres, not more)."""

from __future__ import annotations

import math
from dataclasses import dataclass

EARTH_RADIUS_M = 6_371_000.0


@dataclass(frozen=True)
class Box:
    south: float
    west: float
    north: float
    east: float

    @property
    def centre(self) -> tuple[float, float]:
        return (self.south + self.north) / 2, (self.west + self.east) / 2

    @property
    def height_m(self) -> float:
        return math.radians(self.north - self.south) * EARTH_RADIUS_M

    @property
    def width_m(self) -> float:
        lat = math.radians((self.south + self.north) / 2)
        return math.radians(self.east - self.west) * EARTH_RADIUS_M * math.cos(lat)


def bounding_box(polygon: list[tuple[float, float]]) -> Box | None:
    if not polygon:
        return None
    lats = [p[0] for p in polygon]
    lons = [p[1] for p in polygon]
    return Box(min(lats), min(lons), max(lats), max(lons))


def local_xy(origin: tuple[float, float], point: tuple[float, float]) -> tuple[float, float]:
    """East (x) and north (y) metres of `point` from `origin`, as MOOS local coordinates."""
    lat0 = math.radians(origin[0])
    x = math.radians(point[1] - origin[1]) * EARTH_RADIUS_M * math.cos(lat0)
    y = math.radians(point[0] - origin[0]) * EARTH_RADIUS_M
    return round(x, 1), round(y, 1)
