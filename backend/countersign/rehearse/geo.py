"""A local metric frame for the mission's areas and the few geometric helpers the simulation
needs (point in polygon, distance to a polygon, lawn-mower tracks).

Missions span a few tens of kilometres, so an equirectangular projection around the centre of
all areas is accurate to well under a metre per kilometre; nothing here needs a geodesy
library.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

EARTH_RADIUS_M = 6_371_000.0
Point = tuple[float, float]


@dataclass(frozen=True)
class LocalFrame:
    """x east, y north, in metres from (lat0, lon0)."""

    lat0: float
    lon0: float

    @classmethod
    def around(cls, points: Sequence[tuple[float, float]]) -> LocalFrame:
        if not points:
            return cls(0.0, 0.0)
        lats = [p[0] for p in points]
        lons = [p[1] for p in points]
        return cls((min(lats) + max(lats)) / 2, (min(lons) + max(lons)) / 2)

    def to_xy(self, lat: float, lon: float) -> Point:
        cos0 = math.cos(math.radians(self.lat0))
        return (
            math.radians(lon - self.lon0) * EARTH_RADIUS_M * cos0,
            math.radians(lat - self.lat0) * EARTH_RADIUS_M,
        )


def centroid(polygon: Sequence[Point]) -> Point:
    """Area centroid (vertex mean for degenerate polygons)."""
    n = len(polygon)
    if n == 0:
        return (0.0, 0.0)
    if n < 3:
        return (sum(p[0] for p in polygon) / n, sum(p[1] for p in polygon) / n)
    area2 = cx = cy = 0.0
    for i in range(n):
        x0, y0 = polygon[i]
        x1, y1 = polygon[(i + 1) % n]
        cross = x0 * y1 - x1 * y0
        area2 += cross
        cx += (x0 + x1) * cross
        cy += (y0 + y1) * cross
    if abs(area2) < 1e-9:
        return (sum(p[0] for p in polygon) / n, sum(p[1] for p in polygon) / n)
    return (cx / (3 * area2), cy / (3 * area2))


def contains(polygon: Sequence[Point], point: Point) -> bool:
    """Even-odd rule; polygons with fewer than three points contain nothing."""
    if len(polygon) < 3:
        return False
    x, y = point
    inside = False
    j = len(polygon) - 1
    for i in range(len(polygon)):
        xi, yi = polygon[i]
        xj, yj = polygon[j]
        if (yi > y) != (yj > y) and x < (xj - xi) * (y - yi) / (yj - yi) + xi:
            inside = not inside
        j = i
    return inside


def _segment_distance(p: Point, a: Point, b: Point) -> float:
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    length2 = dx * dx + dy * dy
    if length2 == 0:
        return math.dist(p, a)
    t = max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / length2))
    return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)


def distance_to_polygon(polygon: Sequence[Point], point: Point) -> float:
    """0 inside, else the distance to the nearest edge (or vertex for 1-2 points)."""
    if not polygon:
        return math.inf
    if contains(polygon, point):
        return 0.0
    if len(polygon) == 1:
        return math.dist(polygon[0], point)
    return min(
        _segment_distance(point, polygon[i], polygon[(i + 1) % len(polygon)])
        for i in range(len(polygon))
    )


def bounds(points: Sequence[Point]) -> tuple[float, float, float, float]:
    xs = [p[0] for p in points] or [0.0]
    ys = [p[1] for p in points] or [0.0]
    return (min(xs), min(ys), max(xs), max(ys))


def lawnmower(polygon: Sequence[Point], swath_m: float, max_legs: int = 200) -> list[Point]:
    """Boustrophedon waypoints covering the polygon's bounding box with legs along its longer
    side, `swath_m` apart, shrunk half a swath from the edges (the sensor sees that far).
    Bounded to `max_legs` legs: a narrow swath over a huge area widens instead."""
    x0, y0, x1, y1 = bounds(polygon)
    width, height = x1 - x0, y1 - y0
    along_x = width >= height
    across = height if along_x else width
    legs = max(1, math.ceil(across / max(swath_m, 1.0)))
    if legs > max_legs:
        legs = max_legs
    spacing = across / legs
    points: list[Point] = []
    for k in range(legs):
        offset = spacing * (k + 0.5)
        if along_x:
            y = y0 + offset
            ends = [(x0 + spacing / 2, y), (x1 - spacing / 2, y)]
        else:
            x = x0 + offset
            ends = [(x, y0 + spacing / 2), (x, y1 - spacing / 2)]
        if k % 2:
            ends.reverse()
        points.extend(ends)
    return points


def path_length(points: Sequence[Point]) -> float:
    return sum(math.dist(points[i], points[i + 1]) for i in range(len(points) - 1))
