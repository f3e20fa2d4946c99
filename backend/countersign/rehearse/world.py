"""The simulated world of one rehearsal: areas, charts and shipping lanes, a seafloor, surface
contacts on straight tracks and the recovery point. Everything random is drawn from the
rehearsal's seed, so the same orders and seed give the same world.

The geography is the verifier's (verify/legs.py): the same azimuthal equidistant
frame, the same place for each goal (sweep, station) and the same leg for each outcome edge,
so the rehearsal flies, draws and prices the route that was checked and signed.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from ..orders.model import Area, Orders
from ..verify.legs import Frame, Leg, Place, mission_legs
from .geo import Point, bounds, centroid, distance_to_polygon

LANE_CONTEXTS = frozenset({"shipping_lane", "traffic_lane", "traffic_separation_scheme"})
RECOVERY_CONTEXTS = frozenset({"recovery", "base", "home", "harbor_approach", "launch"})
RECOVERY_IDS = frozenset({"BASE", "HOME", "RECOVERY", "home", "base"})
MAX_CONTACTS = 12
CONTACT_SPEED_MPS = (3.0, 8.0)
GENERATED_LANE_WIDTH_M = 1_500.0
FAR_M = 1e9  # "no contact / no lane": large but finite so records stay valid JSON


@dataclass(frozen=True)
class AreaGeom:
    id: str
    title: str
    polygon: tuple[Point, ...]
    centre: Point
    contexts: frozenset[str]

    @property
    def is_lane(self) -> bool:
        return bool(self.contexts & LANE_CONTEXTS)


@dataclass
class Contact:
    """A surface vessel on a straight track: position at time t is origin + velocity * t."""

    id: str
    origin: Point
    velocity: Point
    start_s: float = 0.0
    closing: bool = False  # injected by the contact_close fault

    def position(self, t: float) -> Point:
        dt = max(0.0, t - self.start_s)
        return (self.origin[0] + self.velocity[0] * dt, self.origin[1] + self.velocity[1] * dt)


class World:
    def __init__(self, orders: Orders, rng: random.Random,
                 charts: tuple[Area, ...] = ()) -> None:
        frame, places, legs = mission_legs(orders)
        # Orders without areas have no frame in the verifier; any centre serves then.
        self.frame: Frame = frame or Frame(0.0, 0.0)
        self.places: dict[str, Place] = places
        self.legs: list[Leg] = legs
        self.areas: dict[str, AreaGeom] = {}
        for area in orders.areas:
            if area.polygon and area.id not in self.areas:
                self.areas[area.id] = self._geom(area)
        # Charts are drawn (the orders' own and the registry's in use), never flown.
        self.charts: list[AreaGeom] = []
        seen: set[str] = set()
        for chart in (*orders.charts, *charts):
            if chart.polygon and chart.id not in seen:
                seen.add(chart.id)
                self.charts.append(self._geom(chart))
        all_xy = [p for a in self.areas.values() for p in a.polygon] or [(0.0, 0.0)]
        x0, y0, x1, y1 = bounds(all_xy)
        margin = max(2_000.0, 0.15 * max(x1 - x0, y1 - y0))
        self.extent = (x0 - margin, y0 - margin, x1 + margin, y1 + margin)
        self.lanes: list[AreaGeom] = [a for a in self.areas.values() if a.is_lane]
        self.generated_lane = not self.lanes
        if self.generated_lane:
            self.lanes.append(self._generated_lane(rng))
        self.recovery = self._recovery_point(orders)
        # The seafloor is deeper than every depth the orders ask for, so ordered depths are
        # physically possible; its relief is seeded.
        deepest = max(
            [hi for g in orders.goals for name, (_, hi) in g.envelope.items() if name == "depth_m"]
            or [50.0]
        )
        self.floor_base_m = max(60.0, deepest * 1.5 + 20.0)
        self._relief = (rng.uniform(2_000, 6_000), rng.uniform(2_000, 6_000),
                        rng.uniform(0, math.tau), rng.uniform(0, math.tau))
        self.contacts: list[Contact] = []
        for k in range(min(2, MAX_CONTACTS)):
            self.contacts.append(self._lane_contact(f"V{k + 1}", rng))

    # -----------------------------------------------------------------------------------------

    def _geom(self, area: Area) -> AreaGeom:
        """The area in the frame; its centre is the verifier's station (the centroid, or a
        point inside when the centroid falls outside)."""
        shape = self.frame.polygon(area.polygon)
        if shape is None:
            xs, ys = self.frame.to_xy([p[0] for p in area.polygon], [p[1] for p in area.polygon])
            polygon = tuple((float(x), float(y)) for x, y in zip(xs, ys, strict=True))
            centre = centroid(polygon)
        else:
            polygon = tuple((float(x), float(y)) for x, y in shape.exterior.coords[:-1])
            inside = shape.centroid if shape.contains(shape.centroid) \
                else shape.representative_point()
            centre = (float(inside.x), float(inside.y))
        kind = getattr(area, "kind", None)
        contexts = frozenset(area.contexts) | ({kind} if kind else set())
        return AreaGeom(area.id, area.title or area.id, polygon, centre, contexts)

    def _generated_lane(self, rng: random.Random) -> AreaGeom:
        """A lane along the long side of the mission, beyond its northern or southern edge."""
        x0, y0, x1, y1 = self.extent
        north = rng.random() < 0.5
        if north:
            ya, yb = y1 + 1_000.0, y1 + 1_000.0 + GENERATED_LANE_WIDTH_M
        else:
            ya, yb = y0 - 1_000.0 - GENERATED_LANE_WIDTH_M, y0 - 1_000.0
        polygon = ((x0, ya), (x1, ya), (x1, yb), (x0, yb))
        return AreaGeom("LANE*", "Shipping lane (generated)", polygon, centroid(polygon),
                        frozenset({"shipping_lane"}))

    def _recovery_point(self, orders: Orders) -> Point:
        for area in self.areas.values():
            if area.id in RECOVERY_IDS or area.contexts & RECOVERY_CONTEXTS:
                return area.centre
        # No recovery area: launch from, and recover to, the first goal's area.
        goals = orders.goal_index()
        start = orders.start if isinstance(orders.start, str) else None
        goal = goals.get(start) if start else None
        if goal and goal.area and goal.area in self.areas:
            x, y = self.areas[goal.area].centre
            return (x - 500.0, y - 500.0)
        return (0.0, 0.0)

    def _lane_contact(self, name: str, rng: random.Random) -> Contact:
        lane = rng.choice(self.lanes)
        x0, y0, x1, y1 = bounds(lane.polygon)
        speed = rng.uniform(*CONTACT_SPEED_MPS)
        if x1 - x0 >= y1 - y0:
            y = rng.uniform(y0, y1)
            eastbound = rng.random() < 0.5
            origin = (x0 if eastbound else x1, y)
            velocity = (speed if eastbound else -speed, 0.0)
        else:
            x = rng.uniform(x0, x1)
            northbound = rng.random() < 0.5
            origin = (x, y0 if northbound else y1)
            velocity = (0.0, speed if northbound else -speed)
        # Start somewhere along the lane rather than always at its end.
        lead = rng.uniform(0.0, 0.8) * math.dist((x0, y0), (x1, y1)) / speed
        origin = (origin[0] + velocity[0] * lead, origin[1] + velocity[1] * lead)
        return Contact(name, origin, velocity)

    def closing_contact(self, vehicle: Point, heading_rad: float, t: float,
                        rng: random.Random) -> Contact | None:
        """The contact_close fault: a vessel whose track passes a few hundred metres from the
        vehicle's position about five minutes from now, so it closes inside 1,000 m."""
        if len(self.contacts) >= MAX_CONTACTS:
            return None
        speed = rng.uniform(4.0, 7.0)
        miss = rng.uniform(150.0, 500.0)
        lead_s = 300.0
        course = heading_rad + math.pi / 2  # crossing the vehicle's track
        cpa = (vehicle[0] + miss * math.cos(heading_rad), vehicle[1] + miss * math.sin(heading_rad))
        velocity = (speed * math.cos(course), speed * math.sin(course))
        origin = (cpa[0] - velocity[0] * lead_s, cpa[1] - velocity[1] * lead_s)
        contact = Contact(f"V{len(self.contacts) + 1}", origin, velocity, start_s=t, closing=True)
        self.contacts.append(contact)
        return contact

    # -----------------------------------------------------------------------------------------

    def seafloor_depth(self, x: float, y: float) -> float:
        lx, ly, px, py = self._relief
        return self.floor_base_m + 15.0 * math.sin(x / lx + px) * math.cos(y / ly + py)

    def lane_distance(self, point: Point) -> float:
        return min((distance_to_polygon(lane.polygon, point) for lane in self.lanes), default=FAR_M)

    def contact_distance(self, point: Point, t: float) -> float:
        best = FAR_M
        for contact in self.contacts:
            if t < contact.start_s:
                continue
            best = min(best, math.dist(point, contact.position(t)))
        return best

    def to_latlon(self, point: Point) -> tuple[float, float]:
        lats, lons = self.frame.to_latlon([point[0]], [point[1]])
        return float(lats[0]), float(lons[0])
