"""The target vehicle's profile as the checks and the plain text use it."""

from __future__ import annotations

from .model import Orders, Vehicle


def is_stub(vehicle: Vehicle) -> bool:
    """A vehicle entry that only names the vehicle (an AVCL `vehicleName`): it lists no
    behaviour, feature or envelope, so nothing about the vehicle can be checked against it."""
    return not (vehicle.behaviors or vehicle.features or vehicle.envelope)


def profile_of(orders: Orders) -> Vehicle | None:
    """The profile of the target vehicle that the checks can use, or None."""
    vehicle = orders.target_vehicle()
    return None if vehicle is None or is_stub(vehicle) else vehicle
