"""The target vehicle's profile: VEHICLE when there is none, M7 for an untrusted behaviour.

M6 and M7 decide whether the vehicle can test each constraint and perform each goal; without
a profile they cannot be decided, and a mission that passes them silently would be signed for
a vehicle nobody checked. Seed 000 (III.D) also requires every phase of a mission to be one of
the vehicle's available trusted behaviours: a goal whose behaviour the vehicle does not trust is
M7 as well. What it trusts is `orders.profile.trusted_behaviors` (DESIGN.md's rule: the profile's
`behaviors` list, or else what its features fulfil).
"""

from __future__ import annotations

from collections.abc import Callable

from ..orders.findings import Finding, error
from ..orders.model import Orders, Vehicle
from ..orders.profile import is_stub, lists_behaviors, profile_of, trusted_behaviors

RegistryLookup = Callable[[str], Vehicle | None]

__all__ = ["RegistryLookup", "check_vehicle", "is_stub", "profile_of", "with_registry_profile"]


def with_registry_profile(orders: Orders, lookup: RegistryLookup | None) -> Orders:
    """The orders with the registry's profile of their target vehicle copied in, when they name
    a vehicle and carry no profile of it: the profile is then inside the orders' digest, so an
    approval covers exactly the profile that was checked."""
    target = orders.vehicle
    if target is None:
        stub = orders.target_vehicle()
        target = stub.id if stub is not None else None
    if lookup is None or target is None or profile_of(orders) is not None:
        return orders
    profile = lookup(target)
    if profile is None or profile.id != target:
        return orders
    others = [v for v in orders.vehicles if v.id != target]
    return orders.model_copy(update={"vehicles": [*others, profile], "vehicle": target})


def check_vehicle(orders: Orders) -> list[Finding]:
    vehicle = profile_of(orders)
    if vehicle is None:
        return [_missing(orders)]
    trusted = trusted_behaviors(vehicle)
    listed = ", ".join(trusted) or "none"
    if not lists_behaviors(vehicle):
        listed += "; the profile lists no behaviours, so those its features fulfil"
    findings = []
    for goal in orders.goals:
        if goal.behavior and goal.behavior not in trusted:
            findings.append(error(
                "M7", [goal.id, vehicle.id],
                f"Vehicle {vehicle.id} lacks the capability for goal {goal.id}"
                f"{f' ({goal.title})' if goal.title else ''}: its behaviour {goal.behavior!r} "
                f"is not among the vehicle's trusted behaviours ({listed}) (seed 000 III.D).",
                rules=["M7", "III.D"], behavior=goal.behavior,
            ))
    return findings


def _missing(orders: Orders) -> Finding:
    stub = orders.target_vehicle()
    if stub is not None:
        where = (f"The orders name vehicle {stub.id} but list none of its behaviours, "
                 "features or envelope, and the server's registry has no profile of it")
        subjects = [orders.id, stub.id]
    elif orders.vehicle is not None:
        where = (f"The orders name vehicle {orders.vehicle} but carry no profile of it, and "
                 "the server's registry has none")
        subjects = [orders.id, orders.vehicle]
    elif orders.vehicles:
        where = (f"The orders carry {len(orders.vehicles)} vehicle profiles but name none of "
                 "them as the target vehicle")
        subjects = [orders.id]
    else:
        where = "The orders name no target vehicle and carry no vehicle profile"
        subjects = [orders.id]
    return error(
        "VEHICLE", subjects,
        f"{where}: whether the vehicle can test the constraints (M6) and perform the goals "
        "(M7) cannot be decided. Add the profile to the orders or to the vehicle registry.",
    )
