"""Where each goal runs and the legs between goals, in a proper projection.

A goal with an area runs a sweep (search behaviours: a lawn-mower clipped to the area) or holds
at a station inside it (a loiter circles it). The leg of an outcome edge goes from where the goal
ends to where its successor starts. Geometry is tested in an azimuthal equidistant projection
centred on the mission, where straight lines stand for the short geodesics between goals;
lengths are geodesic on WGS84 (pyproj.Geod). The GEO check, the budgets and the plan view all
read these legs, so they agree on one route.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache, lru_cache
from typing import TYPE_CHECKING

from ..orders.model import OUTCOMES, Area, Goal, Orders

if TYPE_CHECKING:
    # numpy, shapely and pyproj load when a mission has areas (`mission_legs` of orders
    # without any imports none of them).
    import numpy as np
    from pyproj import Geod, Transformer
    from shapely.geometry import LineString, Point, Polygon

SEARCH_BEHAVIORS = frozenset({"area_search", "search", "survey", "patrol", "coverage"})
TRANSECT_BEHAVIORS = frozenset({"transect"})  # one run along the area's long side
DEFAULT_SWATH_M = 200.0  # as the rehearsal's simulation
MAX_SWEEP_LINES = 200
DEFAULT_LOITER_RADIUS_M = 100.0
MAX_LOITER_RADIUS_M = 50_000.0
LatLon = tuple[float, float]


@cache
def geod() -> Geod:
    """Geodesics on WGS84."""
    from pyproj import Geod

    return Geod(ellps="WGS84")


@dataclass(frozen=True)
class Frame:
    lat0: float
    lon0: float

    def to_xy(self, lats: Sequence[float] | np.ndarray,
              lons: Sequence[float] | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        import numpy as np

        xs, ys = _forward(self.lat0, self.lon0).transform(np.asarray(lons), np.asarray(lats))
        return np.asarray(xs), np.asarray(ys)

    def to_latlon(self, xs: Sequence[float] | np.ndarray,
                  ys: Sequence[float] | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        import numpy as np

        lons, lats = _forward(self.lat0, self.lon0).transform(
            np.asarray(xs), np.asarray(ys), direction="INVERSE")
        return np.asarray(lats), np.asarray(lons)

    def polygon(self, points: Sequence[LatLon]) -> Polygon | None:
        return self.polygons([points])[0]

    def polygons(self, rings: Sequence[Sequence[LatLon]]) -> list[Polygon | None]:
        """Areas' polygons in the frame (one projection call for all of them)."""
        import numpy as np

        flat = [p for ring in rings for p in ring]
        if not flat:
            return [None] * len(rings)
        xs, ys = self.to_xy([p[0] for p in flat], [p[1] for p in flat])
        result: list[Polygon | None] = []
        at = 0
        for ring in rings:
            result.append(_shape(np.column_stack([xs[at:at + len(ring)], ys[at:at + len(ring)]]))
                          if len(ring) >= 3 else None)
            at += len(ring)
        return result


def _shape(coords: np.ndarray) -> Polygon | None:
    """The polygon, repaired if it self-intersects; None if degenerate."""
    import shapely
    from shapely.geometry import Polygon

    shape = Polygon(coords)
    if not shape.is_valid:
        repaired = shapely.make_valid(shape)
        polys = [g for g in getattr(repaired, "geoms", [repaired]) if g.geom_type == "Polygon"]
        shape = max(polys, key=lambda g: g.area) if polys else shape
    return shape if shape.area > 0 else None


@lru_cache(maxsize=64)
def _forward(lat0: float, lon0: float) -> Transformer:
    """Longitude and latitude on WGS84 to the frame's metres (and back, INVERSE).

    The operation PROJ chooses for EPSG:4326 (longitude first) to the azimuthal equidistant CRS
    of WGS84 centred on the frame, written out as its pipeline: looking the two CRSs up in
    PROJ's database costs about 2 % of a `countersign validate` process, the pipeline nothing
    (tests/verify/test_geo.py holds it to `Transformer.from_crs` bit for bit).
    """
    from pyproj import Transformer

    return Transformer.from_pipeline(
        "+proj=pipeline +step +proj=unitconvert +xy_in=deg +xy_out=rad "
        f"+step +proj=aeqd +lat_0={lat0!r} +lon_0={lon0!r} +x_0=0 +y_0=0 +ellps=WGS84")


def frame_for(areas: Sequence[Area]) -> Frame | None:
    points = [p for area in areas for p in area.polygon]
    if not points:
        return None
    lats = [p[0] for p in points]
    lons = [p[1] for p in points]
    # Rounded so that one transformer serves every validation of a mission.
    return Frame(round((min(lats) + max(lats)) / 2, 4), round((min(lons) + max(lons)) / 2, 4))


@dataclass(frozen=True)
class Place:
    """Where one goal runs, in the frame."""

    goal: str
    behavior: str
    area: str
    start: tuple[float, float]
    end: tuple[float, float]
    track: LineString | None  # a sweep
    loiter: Polygon | None
    station: Point | None


@dataclass(frozen=True)
class Leg:
    goal: str
    outcome: str
    to: str
    line: LineString
    start: LatLon
    end: LatLon
    length_m: float


def _number(goal: Goal, *names: str) -> float | None:
    for name in names:
        value = goal.params.get(name)
        if isinstance(value, int | float) and not isinstance(value, bool) and value > 0:
            return float(value)
    return None


def sweep(shape: Polygon, swath_m: float) -> LineString | None:
    """Lawn-mower lines along the longer side of the bounding box, clipped to the area."""
    from shapely.geometry import LineString

    x0, y0, x1, y1 = shape.bounds
    along_x = (x1 - x0) >= (y1 - y0)
    across = (y1 - y0) if along_x else (x1 - x0)
    count = min(MAX_SWEEP_LINES, max(1, math.ceil(across / max(swath_m, 1.0))))
    spacing = across / count
    coords: list[tuple[float, float]] = []
    for k in range(count):
        offset = spacing * (k + 0.5)
        if along_x:
            line = LineString([(x0 - 1, y0 + offset), (x1 + 1, y0 + offset)])
        else:
            line = LineString([(x0 + offset, y0 - 1), (x0 + offset, y1 + 1)])
        inside = line.intersection(shape)
        parts = [g for g in getattr(inside, "geoms", [inside])
                 if g.geom_type == "LineString" and not g.is_empty]
        ends = [c for part in parts for c in part.coords]
        if not ends:
            continue
        ends.sort(key=lambda c: c[0] if along_x else c[1], reverse=bool(k % 2))
        coords.extend((float(c[0]), float(c[1])) for c in (ends[0], ends[-1]))
    return LineString(coords) if len(coords) >= 2 else None


def place(goal: Goal, shape: Polygon) -> Place:
    behavior = (goal.behavior or "").lower()
    station = shape.centroid if shape.contains(shape.centroid) else shape.representative_point()
    if behavior in SEARCH_BEHAVIORS or behavior in TRANSECT_BEHAVIORS:
        swath = math.inf if behavior in TRANSECT_BEHAVIORS else \
            _number(goal, "swath_width_m", "sweep_width_m") or DEFAULT_SWATH_M
        track = sweep(shape, swath)
        if track is not None:
            first, last = track.coords[0], track.coords[-1]
            return Place(goal.id, behavior, goal.area or "", (first[0], first[1]),
                         (last[0], last[1]), track, None, None)
    radius = _number(goal, "loiter_radius_m")
    if radius is None and behavior == "loiter":
        radius = DEFAULT_LOITER_RADIUS_M
    loiter = station.buffer(min(radius, MAX_LOITER_RADIUS_M)) if radius else None
    xy = (float(station.x), float(station.y))
    return Place(goal.id, behavior, goal.area or "", xy, xy, None, loiter, station)


def track_length_m(goal: Goal, areas: Sequence[Area], area: Area) -> float | None:
    """Geodesic metres of the goal's sweep or run in the area, as `places` lays it out in the
    mission's frame (the frame of all of `areas`), or None when the goal holds a station.
    The BUDGET check estimates a goal's cost from it and the rehearsal flies it, so the two
    price one track."""
    behavior = (goal.behavior or "").lower()
    if behavior not in SEARCH_BEHAVIORS and behavior not in TRANSECT_BEHAVIORS:
        return None
    frame = frame_for(areas)
    if frame is None or len(area.polygon) < 3:
        return None
    swath = _number(goal, "swath_width_m", "sweep_width_m")
    return _track_m(frame, behavior, swath, tuple(tuple(p) for p in area.polygon))


@lru_cache(maxsize=4096)
def _track_m(frame: Frame, behavior: str, swath: float | None,
             polygon: tuple[tuple[float, ...], ...]) -> float | None:
    shape = frame.polygon([(p[0], p[1]) for p in polygon])
    if shape is None:
        return None
    width = math.inf if behavior in TRANSECT_BEHAVIORS else swath or DEFAULT_SWATH_M
    track = sweep(shape, width)
    if track is None:
        return None
    xs, ys = zip(*track.coords, strict=True)
    lats, lons = frame.to_latlon(xs, ys)
    return float(geod().line_length(lons, lats))


def places(orders: Orders, frame: Frame) -> dict[str, Place]:
    areas = orders.area_index()
    used = sorted({g.area for g in orders.goals if g.area is not None and g.area in areas})
    shapes = dict(zip(used, frame.polygons([areas[a].polygon for a in used]), strict=True))
    result: dict[str, Place] = {}
    for goal in orders.goals:
        if goal.id in result or goal.area is None or goal.area not in areas:
            continue
        shape = shapes[goal.area]
        if shape is not None:
            result[goal.id] = place(goal, shape)
    return result


def legs(orders: Orders, frame: Frame, where: dict[str, Place]) -> list[Leg]:
    """One leg per outcome edge between two goals that both have a place."""
    from shapely.geometry import LineString

    pending: list[tuple[str, str, str, tuple[float, float], tuple[float, float]]] = []
    seen: set[str] = set()
    for goal in orders.goals:
        if goal.id in seen or goal.id not in where:
            continue
        seen.add(goal.id)
        for outcome in OUTCOMES:
            for target in goal.successors(outcome):
                if target in where:
                    pending.append((goal.id, outcome, target, where[goal.id].end,
                                    where[target].start))
    if not pending:
        return []
    xs0 = [p[3][0] for p in pending]
    ys0 = [p[3][1] for p in pending]
    xs1 = [p[4][0] for p in pending]
    ys1 = [p[4][1] for p in pending]
    lat0, lon0 = frame.to_latlon(xs0, ys0)
    lat1, lon1 = frame.to_latlon(xs1, ys1)
    _, _, lengths = geod().inv(lon0, lat0, lon1, lat1)
    return [
        Leg(g, o, t, LineString([a, b]), (float(lat0[i]), float(lon0[i])),
            (float(lat1[i]), float(lon1[i])), float(lengths[i]))
        for i, (g, o, t, a, b) in enumerate(pending)
    ]


# The frame, where each goal runs, and the leg of each outcome edge: computed once per
# validation and shared by the budget and the GEO check.
MissionLegs = tuple[Frame | None, dict[str, Place], list[Leg]]


def mission_legs(orders: Orders) -> MissionLegs:
    frame = frame_for(orders.areas)
    if frame is None:
        return None, {}, []
    where = places(orders, frame)
    return frame, where, legs(orders, frame, where)


def leg_lengths(orders: Orders, legs: MissionLegs | None = None) -> dict[tuple[str, str], float]:
    """Geodesic metres of the leg of each outcome edge (goal, outcome) that has one."""
    _, _, found = legs if legs is not None else mission_legs(orders)
    return {(leg.goal, leg.outcome): leg.length_m for leg in found}
