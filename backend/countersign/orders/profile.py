"""The target vehicle's profile as the checks and the plain text use it."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the rules' help and design checks read profiles without loading pydantic
    from .model import Orders, Vehicle


def is_stub(vehicle: Vehicle) -> bool:
    """A vehicle entry that only names the vehicle (an AVCL `vehicleName`): it lists no
    behaviour, feature or envelope, so nothing about the vehicle can be checked against it."""
    return not (vehicle.behaviors or vehicle.features or vehicle.envelope)


def profile_of(orders: Orders) -> Vehicle | None:
    """The profile of the target vehicle that the checks can use, or None."""
    vehicle = orders.target_vehicle()
    return None if vehicle is None or is_stub(vehicle) else vehicle


def lists_behaviors(vehicle: Vehicle) -> bool:
    """Whether the profile gives its own `behaviors` list. An empty list counts as none given:
    the editor writes one when its field is cleared, and a vehicle that trusts nothing is
    a profile whose features fulfil nothing."""
    return bool(vehicle.behaviors)


def trusted_behaviors(vehicle: Vehicle) -> list[str]:
    """The vehicle's trusted behaviours (seed 000 III.D), in the order the profile names them:
    its `behaviors` list when it gives one, otherwise the behaviours its features fulfil, so
    profiles written as DESIGN.md shows them (features only) trust what they can do."""
    if lists_behaviors(vehicle):
        return list(dict.fromkeys(vehicle.behaviors))
    return list(dict.fromkeys(b for f in vehicle.features for b in f.fulfills))
