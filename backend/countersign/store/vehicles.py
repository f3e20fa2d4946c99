"""The server's vehicle registry as the checks see it.

Orders that name a vehicle without carrying its profile get the registry's profile copied in
before they are validated and stored, so the version (and so the approval's digest) contains
exactly the profile M6, M7 and BUDGET were checked against; a later change to the registry
cannot change what an approval covered.
"""

from __future__ import annotations

from pydantic import ValidationError
from sqlalchemy.orm import Session

from ..orders.model import Orders, Vehicle
from ..verify.vehicle import with_registry_profile
from .tables import VehicleProfile


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

    profiled = with_registry_profile(orders, lambda vehicle_id: registry_profile(db, vehicle_id))
    return with_registry_charts(db, profiled)
