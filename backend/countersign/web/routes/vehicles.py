"""The vehicle registry's history: every saved profile of a vehicle, for the admin's diff and
for the "needs re-approval" notice on approvals whose profile the registry has since changed."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated

from fastapi import APIRouter, Path
from pydantic import BaseModel

from ...errors import NotFound
from ...store.vehicles import vehicle_versions
from ..deps import EVERYONE, Db, TransactionRoute, allow
from .schemas import VehicleJson

router = APIRouter(prefix="/api", tags=["administration"], route_class=TransactionRoute)

VehicleId = Annotated[str, Path(min_length=1, max_length=100)]


class VehicleVersionOut(BaseModel):
    vehicle_id: str
    number: int
    title: str
    profile: VehicleJson
    saved_by: str | None
    saved_at: datetime


@router.get("/vehicles/{vehicle_id}/versions", operation_id="listVehicleVersions",
            response_model=list[VehicleVersionOut], **allow(*EVERYONE))
def list_vehicle_versions(vehicle_id: VehicleId, db: Db) -> list[VehicleVersionOut]:
    versions = vehicle_versions(db, vehicle_id)
    if not versions:
        raise NotFound(f"the registry has no vehicle {vehicle_id!r}")
    return [VehicleVersionOut(vehicle_id=v.vehicle_id, number=v.number, title=v.title,
                              profile=v.profile, saved_by=v.saved_by, saved_at=v.saved_at)
            for v in versions]
