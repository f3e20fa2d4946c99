"""GEO: legs, sweeps and loiters that enter a charted area a norm forbids.

Only waypoints used to be checked; here every outcome edge's leg (behaviour 'transit'), every
sweep and every loiter is tested against the mission's areas and the registry charts copied into
the orders, with an STRtree so that hundreds of charts cost one index query. A leg breaks an area
when it crosses it (enters its interior from outside, or leaves it): a leg entirely inside, or
touching the boundary only, does not. Sweeps and loiters break an area they overlap at all.
What forbids: the tags `keep_out` and `land` (and the bundled land mask), a chart's own norms,
and the mission's norms whose context is one of the area's tags (or an expression that holds).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

from ..orders.findings import Finding, error, warning
from ..orders.model import OUTCOMES, Area, Chart, Orders
from .expressions import ExprError, Facts, fold, parse
from .graph import MissionGraph, build_graph
from .legs import Frame, Leg, MissionLegs, Place, mission_legs

if TYPE_CHECKING:
    # Loaded by the checks of a mission with areas (legs.py), not by this module.
    import shapely
    from shapely.geometry import LineString, Polygon
    from shapely.geometry.base import BaseGeometry

MAX_FINDINGS = 500
FORBIDDING_TAGS = {"keep_out": "keep-out area", "land": "land"}


@dataclass(frozen=True)
class Region:
    id: str
    title: str
    tags: frozenset[str]
    shape: Polygon
    chart: Chart | None

    @property
    def label(self) -> str:
        what = "chart" if self.chart is not None else "area"
        return f"{what} {self.id}" + (f" ({self.title})" if self.title else "")


@lru_cache(maxsize=4096)
def _holds(source: str, behavior: str, area: str, tags: frozenset[str]) -> bool:
    try:
        expr = parse(source)
    except ExprError:
        return False  # EXPR reports it
    return fold(expr, Facts(behavior, area, tags)) is True


class Rules:
    """Why an area forbids a behaviour there, or None."""

    def __init__(self, orders: Orders) -> None:
        self.norms = list(orders.norms)
        self._cache: dict[tuple[str, str], str | None] = {}

    def forbids(self, region: Region, behavior: str) -> str | None:
        key = (region.id, behavior)
        if key not in self._cache:
            self._cache[key] = self._why(region, behavior)
        return self._cache[key]

    def _why(self, region: Region, behavior: str) -> str | None:
        kind = region.chart.kind if region.chart is not None else None
        for tag, words in FORBIDDING_TAGS.items():
            if tag in region.tags or kind == tag:
                return f"it is {words}: no part of the mission may enter it"
        for chart_norm in region.chart.norms if region.chart is not None else ():
            if _holds(chart_norm.forbidden, behavior, region.id, region.tags):
                text = chart_norm.text or chart_norm.forbidden
                return f"its norm {chart_norm.id} forbids {behavior} there ({text!r})"
        for norm in self.norms:
            context = norm.context.strip()
            applies = context in region.tags or (
                not context.isidentifier() and _holds(context, behavior, region.id, region.tags))
            if applies and norm.forbidden and _holds(norm.forbidden, behavior, region.id,
                                                     region.tags):
                text = norm.text or norm.forbidden
                return f"norm {norm.id} forbids {behavior} in {context} ({text!r})"
        return None


def regions(orders: Orders, frame: Frame) -> list[Region]:
    found: list[Region] = []
    unique: dict[str, Area] = {}
    for area in [*orders.areas, *orders.charts]:
        unique.setdefault(area.id, area)
    areas = list(unique.values())
    for area, shape in zip(areas, frame.polygons([a.polygon for a in areas]), strict=True):
        if shape is not None:
            tags = frozenset(area.contexts)
            found.append(Region(area.id, area.title, tags, shape,
                                area if isinstance(area, Chart) else None))
    return found


def crosses(leg: LineString, shape: Polygon) -> bool:
    """The leg passes through the area's interior and also runs outside it."""
    import shapely

    return bool(shapely.crosses(leg, shape))


def enters(geometry: BaseGeometry, shape: Polygon) -> bool:
    """Some part of a sweep, loiter or station lies in the area's interior."""
    import shapely

    return bool(shapely.relate_pattern(geometry, shape, "T********"))


class _Paths:
    """A path from the start that takes a given edge, for the finding's counterexample."""

    def __init__(self, graph: MissionGraph) -> None:
        self.graph = graph
        self.index = {gid: n for n, gid in enumerate(graph.goal_ids)}
        self._onward: dict[int, int] | None = None
        self._memo: dict[tuple[str, str], dict[str, object] | None] = {}

    def onward(self) -> dict[int, int]:
        """Per goal, an outcome that leads to a terminal (backward breadth-first search)."""
        if self._onward is None:
            graph = self.graph
            choice: dict[int, int] = {}
            done: set[int] = set(range(graph.goal_count, graph.goal_count + len(graph.terminals)))
            changed = True
            while changed:
                changed = False
                for node in range(graph.goal_count):
                    if node in choice:
                        continue
                    for k, target in enumerate(graph.succ[node]):
                        if target in done:
                            choice[node] = k
                            done.add(node)
                            changed = True
                            break
            self._onward = choice
        return self._onward

    def through(self, goal: str, outcome: str) -> dict[str, object] | None:
        key = (goal, outcome)
        if key not in self._memo:
            self._memo[key] = self._through(goal, outcome)
        return self._memo[key]

    def _through(self, goal: str, outcome: str) -> dict[str, object] | None:
        graph = self.graph
        node = self.index.get(goal)
        if node is None:
            return None
        prefix = graph.outcomes_to(node)
        if prefix is None:
            return None
        goals: list[str] = []
        outcomes: list[str] = []
        walk = graph.start
        for step in [*prefix, outcome]:
            assert walk is not None
            goals.append(graph.goal_ids[walk])
            outcomes.append(step)
            walk = graph.succ[walk][OUTCOMES.index(step)]
        onward = self.onward()
        guard = 0
        while walk is not None and 0 <= walk < graph.goal_count and guard <= graph.goal_count:
            k = onward.get(walk)
            if k is None:
                return None
            goals.append(graph.goal_ids[walk])
            outcomes.append(OUTCOMES[k])
            walk = graph.succ[walk][k]
            guard += 1
        if walk is None or walk < graph.goal_count:
            return None
        return {"goals": goals, "outcomes": outcomes, "terminal": graph.node_id(walk)}


def _path_words(path: dict[str, object] | None) -> str:
    if path is None:
        return " No path from the start takes this edge."
    pairs = [f"{g} {o}" for g, o in zip(path["goals"], path["outcomes"],  # type: ignore[call-overload]
                                         strict=True)]
    if len(pairs) > 12:  # the finding's path holds every step
        pairs = [*pairs[:5], f"... {len(pairs) - 10} more ...", *pairs[-5:]]
    steps = ", ".join(pairs)
    return f" A path that takes it: {steps} -> {path['terminal']}."


def check_geo(orders: Orders, graph: MissionGraph | None = None,
              legs: MissionLegs | None = None) -> list[Finding]:
    frame, where, found_legs = legs if legs is not None else mission_legs(orders)
    if frame is None:
        return []
    graph = graph or build_graph(orders)
    paths = _Paths(graph)
    rules = Rules(orders)
    zones = regions(orders, frame)
    findings: list[Finding] = []
    if zones:
        import shapely

        tree = shapely.STRtree([z.shape for z in zones])
        findings.extend(_leg_findings(found_legs, where, zones, tree, rules, paths))
        findings.extend(_place_findings(where, zones, tree, rules))
    findings.extend(_land_findings(frame, found_legs, where, paths))
    if len(findings) > MAX_FINDINGS:
        dropped = len(findings) - MAX_FINDINGS
        findings = findings[:MAX_FINDINGS]
        findings.append(warning("GEO", [orders.id], f"{dropped} further GEO findings are not "
                                "listed; fix the ones above and validate again."))
    return findings


def _leg_findings(found_legs: list[Leg], where: dict[str, Place], zones: list[Region],
                  tree: shapely.STRtree, rules: Rules, paths: _Paths) -> list[Finding]:
    if not found_legs:
        return []
    import numpy as np
    import shapely

    lines = np.array([leg.line for leg in found_legs], dtype=object)
    leg_idx, zone_idx = tree.query(lines, predicate="intersects")
    if len(leg_idx) == 0:
        return []
    hits = shapely.crosses(lines[leg_idx], np.array([z.shape for z in zones],
                                                    dtype=object)[zone_idx])
    findings: list[Finding] = []
    for i, z in zip(leg_idx[hits].tolist(), zone_idx[hits].tolist(), strict=True):
        if len(findings) > MAX_FINDINGS:
            break  # check_geo says how many more there are not
        leg, zone = found_legs[i], zones[z]
        if zone.id in (where[leg.goal].area, where[leg.to].area) and not _forbids_all(zone):
            continue  # leaving or reaching a goal's own area: NORM judges the goal there
        why = rules.forbids(zone, "transit")
        if why is None:
            continue
        path = paths.through(leg.goal, leg.outcome)
        findings.append(error(
            "GEO", [leg.goal, leg.outcome, zone.id],
            f"The leg from {leg.goal} on {leg.outcome} to {leg.to} ({leg.length_m:,.0f} m) "
            f"crosses {zone.label}, where {why}.{_path_words(path)}",
            edge={"goal": leg.goal, "outcome": leg.outcome, "to": leg.to}, area=zone.id,
            element="leg", path=path,
        ))
    return findings


def _forbids_all(zone: Region) -> bool:
    kind = zone.chart.kind if zone.chart is not None else None
    return any(tag in zone.tags or kind == tag for tag in FORBIDDING_TAGS)


def _place_findings(where: dict[str, Place], zones: list[Region], tree: shapely.STRtree,
                    rules: Rules) -> list[Finding]:
    findings = []
    for place in where.values():
        element, shape = ("sweep", place.track) if place.track is not None else (
            ("loiter", place.loiter) if place.loiter is not None else ("station", place.station))
        if shape is None:
            continue
        for z in tree.query(shape, predicate="intersects").tolist():
            zone = zones[z]
            if zone.id == place.area and not _forbids_all(zone):
                continue  # the goal's own area: NORM's job
            if not enters(shape, zone.shape):
                continue
            why = rules.forbids(zone, place.behavior or "transit")
            if why is None:
                continue
            findings.append(error(
                "GEO", [place.goal, zone.id],
                f"The {element} of goal {place.goal} ({place.behavior or 'no behaviour'}) "
                f"enters {zone.label}, where {why}.",
                goal=place.goal, area=zone.id, element=element,
            ))
    return findings


def _land_findings(frame: Frame, found_legs: list[Leg], where: dict[str, Place],
                   paths: _Paths) -> list[Finding]:
    from .land import land_hits  # numpy and the land mask

    findings = []
    for leg, hit in zip(found_legs, land_hits(frame, [leg.line for leg in found_legs]),
                        strict=True):
        if hit is None:
            continue
        path = paths.through(leg.goal, leg.outcome)
        findings.append(error(
            "GEO", [leg.goal, leg.outcome, "land"],
            f"The leg from {leg.goal} on {leg.outcome} to {leg.to} crosses land near "
            f"{hit[0]:.4f}, {hit[1]:.4f} (bundled land mask).{_path_words(path)}",
            edge={"goal": leg.goal, "outcome": leg.outcome, "to": leg.to}, area="land",
            element="leg", path=path, at=list(hit),
        ))
    sweeps = [place for place in where.values() if place.track is not None]
    for place, hit in zip(sweeps, land_hits(frame, [p.track for p in sweeps]), strict=True):
        if hit is not None:
            findings.append(error(
                "GEO", [place.goal, "land"],
                f"The sweep of goal {place.goal} crosses land near {hit[0]:.4f}, "
                f"{hit[1]:.4f} (bundled land mask).",
                goal=place.goal, area="land", element="sweep", at=list(hit),
            ))
    return findings
