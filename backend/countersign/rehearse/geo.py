"""The few planar helpers the simulation needs in the mission's frame (point in polygon,
distance to a polygon). The frame itself is the verifier's (verify/legs.py: an azimuthal
equidistant projection centred on the mission), so the rehearsal flies the legs that were
checked.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

Point = tuple[float, float]


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
