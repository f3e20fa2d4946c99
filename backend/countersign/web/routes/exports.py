"""Vehicle exports of a mission version (IMC, MOOS-IvP): a listing with notes, and downloads;
a team's version a member at a time (`?member=VEHICLE`)."""

from __future__ import annotations

import hashlib
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Path, Query
from fastapi.responses import Response
from pydantic import BaseModel
from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ...approved_package.build import build_package
from ...errors import NotFound, Unprocessable
from ...export.notes import ExportError, VehicleExport
from ...export.package import export_provenance
from ...export.team import MemberNeeded, UnknownMember
from ...export.vehicle import export_vehicle
from ...orders.reader import orders_from_data
from ...store import missions as service
from ...store.packages import package_parts
from ...store.tables import Approval, MissionVersion
from ..deps import EVERYONE, Db, RowId, TransactionRoute, allow
from .approvals import Signer

router = APIRouter(prefix="/api", tags=["exports"], route_class=TransactionRoute)
VehicleFormat = Literal["imc", "moos"]
FileName = Annotated[str, Path(max_length=220, pattern=r"^[A-Za-z0-9_.:\-]+$")]
# A team's orders are exported a member (vehicle) at a time; ids are at most 200 characters.
MemberQuery = Annotated[str | None, Query(
    max_length=200, description="team orders: the member vehicle whose files to write "
    "(required for a team, refused for one vehicle's orders)")]


class ExportNoteOut(BaseModel):
    code: str
    path: str
    message: str


class ExportFileOut(BaseModel):
    name: str
    media_type: str
    size: int
    sha256: str


class VehicleExportOut(BaseModel):
    format: VehicleFormat
    mission: str
    member: str | None = None
    version: int
    orders_digest: str
    approved: bool
    files: list[ExportFileOut]
    notes: list[ExportNoteOut]


def approval_facts(db: DbSession, version: MissionVersion) -> dict[str, Any] | None:
    """The version's standing approval as the export names it (None: not approved, or the
    approval was revoked)."""
    rows = db.scalars(select(Approval).where(Approval.version_id == version.id)
                      .order_by(Approval.id)).all()
    revoked = {row.revokes for row in rows if row.decision == "revoked"}
    approved = [row for row in rows if row.decision == "approved" and row.id not in revoked]
    if not approved:
        return None
    return export_provenance(approved[-1].envelope)


def _export(db: DbSession, mission_id: str, number: int, fmt: str, member: str | None
            ) -> tuple[MissionVersion, VehicleExport, bool]:
    version = service.get_version(db, mission_id, number)
    approval = approval_facts(db, version)
    try:
        export = export_vehicle(orders_from_data(version.orders), fmt, version=version.number,
                                approval=approval, member=member)
    except (MemberNeeded, UnknownMember) as exc:
        raise Unprocessable(f"member: {exc}") from None
    except ExportError as exc:
        raise Unprocessable(str(exc)) from None
    return version, export, approval is not None


@router.get("/missions/{mission_id}/versions/{number}/vehicle/{format}",
            operation_id="getVehicleExport", response_model=VehicleExportOut,
            **allow(*EVERYONE))
def get_vehicle_export(mission_id: str, number: RowId, format: VehicleFormat,
                             db: Db, member: MemberQuery = None) -> VehicleExportOut:
    version, export, approved = _export(db, mission_id, number, format, member)
    return VehicleExportOut(
        format=format, mission=version.mission_id, member=member, version=version.number,
        orders_digest=version.digest, approved=approved,
        files=[ExportFileOut(name=f.name, media_type=f.media_type, size=len(f.content),
                             sha256="sha256:" + hashlib.sha256(f.content).hexdigest())
               for f in export.files],
        notes=[ExportNoteOut(**n.to_json()) for n in export.notes])


@router.get("/missions/{mission_id}/versions/{number}/vehicle/{format}/{name}",
            operation_id="downloadVehicleExport", response_class=Response,
            responses={200: {"content": {"application/octet-stream": {}}}},
            **allow(*EVERYONE))
def download_vehicle_export(mission_id: str, number: RowId, format: VehicleFormat,
                                  name: FileName, db: Db,
                                  member: MemberQuery = None) -> Response:
    _, export, _ = _export(db, mission_id, number, format, member)
    item = export.file(name)
    if item is None:
        names = ", ".join(f.name for f in export.files)
        raise NotFound(f"this export has no file {name!r} (it has {names})")
    return Response(item.content, media_type=item.media_type, headers={
        "Content-Disposition": f'attachment; filename="{item.name}"',
        "X-Content-Type-Options": "nosniff"})


@router.get("/missions/{mission_id}/versions/{number}/package", operation_id="downloadPackage",
            response_class=Response,
            responses={200: {"content": {"application/x-tar": {}}}}, **allow(*EVERYONE))
def download_package(mission_id: str, number: RowId, db: Db, signer: Signer) -> Response:
    """The approved package of a version (countersign.package/1 tar): orders, vehicle files,
    envelope, receipt, inclusion proof, checkpoint; `countersign vehicle verify` checks it."""
    try:
        data = build_package(package_parts(db, mission_id=mission_id, number=number,
                                           signer=signer))
    except ExportError as exc:
        raise Unprocessable(str(exc)) from None
    return Response(data, media_type="application/x-tar", headers={
        "Content-Disposition": f'attachment; filename="{mission_id}-v{number}.package.tar"',
        "X-Content-Type-Options": "nosniff"})
