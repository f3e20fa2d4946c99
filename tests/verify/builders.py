"""Small helpers to write orders in tests without repeating boilerplate."""

from __future__ import annotations

from typing import Any

from countersign.orders.model import Orders

Next = tuple[str | None, str | None, str | None]


def orders_from(edges: dict[str, Next], start: str | None = "G1", **extra: Any) -> Orders:
    goals = []
    for goal_id, (s, f, v) in edges.items():
        nxt = {k: t for k, t in (("succeed", s), ("fail", f), ("violate", v)) if t is not None}
        goals.append({"id": goal_id, "title": f"Do {goal_id}", "next": nxt})
    data: dict[str, Any] = {"format": "countersign.orders/1", "id": "t", "goals": goals}
    if start is not None:
        data["start"] = start
    data.update(extra)
    return Orders.model_validate(data)


def codes(findings: list[Any]) -> list[str]:
    return [f.code for f in findings]
