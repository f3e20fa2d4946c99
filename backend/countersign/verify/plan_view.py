"""What the plan view draws: areas, charts, each outcome edge's leg, the GEO crossings and the
coastline around the mission, all in latitude/longitude (no map tiles needed)."""

from __future__ import annotations

from typing import Any

from ..orders.model import Orders
from .charts import mission_box
from .geo import check_geo
from .land import coastline
from .legs import mission_legs

COAST_MARGIN_DEG = 0.05


def plan_view(orders: Orders) -> dict[str, Any]:
    computed = mission_legs(orders)
    frame, where, legs = computed
    crossings = []
    for finding in check_geo(orders, legs=computed):
        edge = finding.details.get("edge")
        crossings.append({"subjects": list(finding.subjects), "message": finding.message,
                          "area": finding.details.get("area"), "edge": edge,
                          "goal": finding.details.get("goal"),
                          "element": finding.details.get("element")})
    places = []
    if frame is not None:
        for place in where.values():
            xs, ys = zip(place.start, place.end, strict=True)
            lats, lons = frame.to_latlon(list(xs), list(ys))
            places.append({"goal": place.goal, "area": place.area, "behavior": place.behavior,
                           "start": [float(lats[0]), float(lons[0])],
                           "end": [float(lats[1]), float(lons[1])]})
    box = mission_box(orders, COAST_MARGIN_DEG)
    return {
        "areas": [{"id": a.id, "title": a.title, "contexts": list(a.contexts),
                   "polygon": [list(p) for p in a.polygon]} for a in orders.areas],
        "charts": [{"id": c.id, "title": c.title, "kind": c.kind, "contexts": list(c.contexts),
                    "polygon": [list(p) for p in c.polygon]} for c in orders.charts],
        "places": places,
        "legs": [{"goal": leg.goal, "outcome": leg.outcome, "to": leg.to,
                  "start": list(leg.start), "end": list(leg.end),
                  "length_m": round(leg.length_m, 1)} for leg in legs],
        "crossings": crossings,
        "coastline": [[list(a), list(b)] for a, b in coastline(*box)] if box else [],
        "box": list(box) if box else None,
    }
