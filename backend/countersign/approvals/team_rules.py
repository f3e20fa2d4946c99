"""A team approval's member digests (DESIGN.md "Refinement and teams", README "Teams").

One approval signs a team's orders: the subject is the team's digest and the predicate's
`team` gives every member's digest by vehicle (the member's orders alone, as
`countersign.orders/1`), so a vehicle that loads only its own orders can check it is one
the supervisor signed. The verifiers (audit bundles, approved packages, the browser's
src/crypto/teamRules.ts) recompute those digests from the orders they hold; both run the
vectors in frontend/src/crypto/__fixtures__/team.json and must name the same problems.
"""

from __future__ import annotations

from typing import Any

from .statement import json_digest

# The orders format a member's orders are hashed as (orders.model.FORMAT; the offline verifiers
# read JSON only, so they do not import the model).
ORDERS_FORMAT = "countersign.orders/1"


def member_orders_digests(orders: Any) -> dict[str, str] | None:
    """Each member's orders digest by vehicle, or None when the orders hold no team."""
    members = orders.get("team") if isinstance(orders, dict) else None
    if not isinstance(members, list) or not all(
            isinstance(m, dict) and isinstance(m.get("orders"), dict) for m in members):
        return None
    return {str(m.get("vehicle")): json_digest({**m["orders"], "format": ORDERS_FORMAT})
            for m in members}


def team_problems(orders: Any, predicate: Any) -> list[str]:
    """What is wrong with the member digests a statement's predicate signs for these orders
    (the orders the subject digest covers): each problem names the member. Empty when the
    statement signs exactly the team's members, each with its own orders' digest, or when
    neither the orders nor the statement are a team's."""
    signed = predicate.get("team") if isinstance(predicate, dict) else None
    actual = member_orders_digests(orders)
    if signed is None:
        return [] if actual is None else [
            "the orders hold a team but the statement signs no member digests (predicate.team)"]
    if actual is None:
        return ["the statement signs a team's member digests (predicate.team) but the orders "
                "hold no team"]
    if not isinstance(signed, dict) or not all(isinstance(v, str) for v in signed.values()):
        return ["the statement's predicate.team is not a map of vehicle to orders digest"]
    problems = [f"team member {vehicle}: the statement signs no digest for it"
                for vehicle in actual if vehicle not in signed]
    problems += [f"team member {vehicle}: the statement signs a digest for it but the team "
                 "has no such member" for vehicle in signed if vehicle not in actual]
    problems += [f"team member {vehicle}: the signed digest {signed[vehicle]} is not that of "
                 f"its orders ({digest})"
                 for vehicle, digest in actual.items()
                 if vehicle in signed and signed[vehicle] != digest]
    return problems
