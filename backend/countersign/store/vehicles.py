"""The server's vehicle registry as the checks see it.

Orders that name a vehicle without carrying its profile get the registry's profile copied in
before they are validated and stored, so the version (and so the approval's digest) contains
exactly the profile M6, M7 and BUDGET were checked against; a later change to the registry
cannot change what an approval covered.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import rfc8785
from pydantic import ValidationError
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from ..approvals.signer import LogSigner
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
    """The registry's vehicle profile, the charts in use (store/charts.py) and the procedures
    named (store/procedures.py) copied in."""
    from .charts import with_registry_charts
    from .procedures import with_library

    if orders.team is not None:
        return _team_with_registry(db, orders)
    orders = with_library(db, orders)  # the bodies of the procedures named
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
    from .procedure_tables import ProcedureRecord

    stamps = [db.execute(select(func.count(), func.max(table.updated_at))).one()
              for table in (VehicleProfile, ChartRecord, ProcedureRecord)]
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


def seed_registry(db: Session, vehicles: Iterable[Vehicle], actor: User, *,
                  signer: LogSigner | None) -> list[str]:
    """Saves each profile the registry does not hold yet (the first one of an id wins) and logs
    it as the admin's save would; profiles already registered are left as the admin keeps them.
    For `serve --demo`, so that a new mission's vehicle has a profile from the first run."""
    from .events import record

    seeded: list[str] = []
    for vehicle in vehicles:
        if vehicle.id in seeded or db.get(VehicleProfile, vehicle.id) is not None:
            continue
        _, number = save_vehicle(db, vehicle, actor)
        db.flush()
        record(db, signer=signer, kind="vehicle.saved", actor=actor,
               detail={"vehicle": vehicle.id, "version": number})
        seeded.append(vehicle.id)
    return seeded


# Drafts brought up to a changed profile in one save; the rest follow at their next edit (the
# save answers in bounded time however many missions name the vehicle).
MAX_DRAFTS_REFRESHED = 200


def refresh_drafts(db: Session, vehicle_id: str, previous: dict[str, Any] | None,
                   actor: User, *, signer: LogSigner | None) -> list[str]:
    """After a registry save: the drafts that name the vehicle and carry no profile of it, or
    the registry's previous profile as it was copied in, get the current one (a new revision,
    logged as a draft update by the admin), so their next report is checked against it instead
    of keeping a VEHICLE error or an outdated profile until someone edits them.
    A draft whose operator changed the copied profile is left alone. Versions never change."""
    from ..orders.canonical import orders_to_json
    from ..orders.reader import OrdersReadError, orders_from_data
    from .missions import update_draft
    from .tables import Mission

    current = registry_profile(db, vehicle_id)
    if current is None:
        return []
    stale = None if previous is None else rfc8785.dumps(previous)
    refreshed: list[str] = []
    for mission in db.scalars(select(Mission).where(Mission.vehicle == vehicle_id)
                              .order_by(Mission.id).limit(MAX_DRAFTS_REFRESHED)):
        try:
            orders = orders_from_data(mission.draft)
        except OrdersReadError:  # a draft that no longer reads is not ours to fix
            continue
        carried = [v for v in orders.vehicles if v.id == vehicle_id]
        if carried:
            copied = carried[0].model_dump(mode="json", exclude_unset=True)
            if stale is None or rfc8785.dumps(copied) != stale:
                continue
        updated = orders.model_copy(update={
            "vehicles": [*(v for v in orders.vehicles if v.id != vehicle_id), current]})
        if orders_to_json(updated) == mission.draft:
            continue
        update_draft(db, signer=signer, mission_id=mission.id, orders=updated, layout=None,
                     expected_revision=mission.revision, author=actor)
        refreshed.append(mission.id)
    return refreshed


def vehicle_versions(db: Session, vehicle_id: str) -> list[VehicleVersion]:
    """The vehicle's saved profiles, newest first."""
    return list(db.scalars(select(VehicleVersion).where(VehicleVersion.vehicle_id == vehicle_id)
                           .order_by(VehicleVersion.number.desc()).limit(1000)))
