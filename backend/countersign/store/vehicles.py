"""The server's vehicle registry as the checks see it.

Orders that name a vehicle without carrying its profile get the registry's profile copied in
before they are validated and stored, so the version (and so the approval's digest) contains
exactly the profile M6, M7 and BUDGET were checked against; a later change to the registry
cannot change what an approval covered.
"""

from __future__ import annotations

from typing import Any

import rfc8785
from pydantic import ValidationError
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from ..orders.model import Orders, Vehicle
from ..verify.vehicle import with_registry_profile
from .tables import ChartRecord, User, VehicleProfile, VehicleVersion, utcnow


def registry_profile(db: Session, vehicle_id: str) -> Vehicle | None:
    row = db.get(VehicleProfile, vehicle_id)
    if row is None:
        return None
    try:
        return Vehicle.model_validate(row.profile)
    except ValidationError:
        # A row a database writer broke is no profile: VEHICLE reports the orders unchecked.
        return None


def with_registry(db: Session, orders: Orders) -> Orders:
    """The registry's vehicle profile and the charts in use (store/charts.py) copied in."""
    from .charts import with_registry_charts

    if orders.team is not None:
        return _team_with_registry(db, orders)
    profiled = with_registry_profile(orders, lambda vehicle_id: registry_profile(db, vehicle_id))
    return with_registry_charts(db, profiled)


def _team_with_registry(db: Session, orders: Orders) -> Orders:
    """Each member's orders with the registry's profile of its vehicle and its charts."""
    assert orders.team is not None
    members = [with_registry(db, member.orders) for member in orders.team]
    if all(new is member.orders for new, member in zip(members, orders.team, strict=True)):
        return orders  # nothing copied: the orders (and their digest) stay as written
    data = orders.model_dump(mode="json", exclude_unset=True)
    for entry, new in zip(data["team"], members, strict=True):
        entry["orders"] = new.model_dump(mode="json", exclude_unset=True)
    return Orders.model_validate(data)


def registry_stamp(db: Session) -> bytes:
    """What with_registry reads, in a few bytes: the row count and latest change of the vehicle
    profiles and of the charts. Caches of results computed with the registry copied in key on
    it, so a saved or deleted profile or chart is never answered from before the change."""
    stamps = [db.execute(select(func.count(), func.max(table.updated_at))).one()
              for table in (VehicleProfile, ChartRecord)]
    return repr(stamps).encode()


def save_vehicle(db: Session, vehicle: Vehicle, actor: User) -> tuple[dict[str, Any], int]:
    """Stores the profile as the registry's current one; a profile that differs from the last
    saved one becomes the next version (saving the same profile again adds none)."""
    profile = vehicle.model_dump(mode="json", exclude_unset=True)
    row = db.get(VehicleProfile, vehicle.id)
    if row is None:
        db.add(VehicleProfile(id=vehicle.id, title=vehicle.title, profile=profile))
    else:
        row.title, row.profile, row.updated_at = vehicle.title, profile, utcnow()
    last = db.scalars(select(VehicleVersion).where(VehicleVersion.vehicle_id == vehicle.id)
                      .order_by(VehicleVersion.number.desc()).limit(1)).first()
    if last is not None and rfc8785.dumps(last.profile) == rfc8785.dumps(profile):
        return profile, last.number
    number = 1 if last is None else last.number + 1
    db.add(VehicleVersion(vehicle_id=vehicle.id, number=number, title=vehicle.title,
                          profile=profile, saved_by=actor.username))
    return profile, number


def vehicle_versions(db: Session, vehicle_id: str) -> list[VehicleVersion]:
    """The vehicle's saved profiles, newest first."""
    return list(db.scalars(select(VehicleVersion).where(VehicleVersion.vehicle_id == vehicle_id)
                           .order_by(VehicleVersion.number.desc()).limit(1000)))
