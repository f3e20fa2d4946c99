"""Orders that keep z3 busy: the 6 KB validation (40 nonlinear constraints, 20 path
properties) that ran 76 s before every request had a solver budget."""

from __future__ import annotations

import json
from typing import Any

from countersign.orders.examples import example_bytes

QUANTITIES = ("depth_m", "speed_mps", "altitude_m", "nav_error_m", "lane_distance_m",
              "contact_distance_m")


def heavy_orders(constraints: int = 40, properties: int = 20) -> dict[str, Any]:
    """The exemplar with `constraints` products of three quantities bounded on every goal and
    `properties` path properties over more products: nonlinear real arithmetic, where z3 gives
    up only at its timeout."""
    data: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    data["id"] = "heavy-nonlinear"
    # About the 6 KB: the exemplar's prose goes, its goals and constraints stay.
    data["description"] = ""
    for item in (*data["goals"], *data["constraints"], *data.get("norms", ())):
        item.pop("params", None)
        if "text" in item:
            item["text"] = item["id"]
    q = QUANTITIES
    for j in range(constraints):
        a, b, c, d = q[j % 6], q[(j + 1) % 6], q[(j + 2) % 6], q[(j + 3) % 6]
        data["constraints"].append({
            "id": f"H{j}", "text": f"Bound {j}", "applies_to": "mission",
            "expr": f"{a} * {b} * {c} - {d} * {d} * {a} >= {j + 1}"})
    data["properties"] = [
        {"id": f"P{k}", "always": f"{q[k % 6]} * {q[(k + 2) % 6]} * {q[(k + 4) % 6]} "
                                  f"<= {1000 + k} * {q[(k + 1) % 6]}"}
        for k in range(properties)]
    return data


def heavy_body(constraints: int = 40, properties: int = 20) -> bytes:
    return json.dumps(heavy_orders(constraints, properties), separators=(",", ":")).encode()
