"""The procedure library: operators save procedure versions, supervisors sign a
decision on a version, everyone reads; a mission version says which procedures it uses and
whether a supervisor approved each."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any

from fastapi import APIRouter, Path, Query
from pydantic import BaseModel, Field

from ...orders.model import MAX_PROCEDURE_VERSION
from ...orders.procedure import Procedure, procedure_from_data
from ...orders.reader import orders_from_data
from ...store import procedures as service
from ...store.approvals.common import _username
from ...store.approvals.log import log_index_of
from ...store.missions import get_version
from ...store.procedure_tables import ProcedureApproval, ProcedureRecord
from ..deps import (
    EVERYONE,
    OPERATORS,
    CurrentPrincipal,
    Db,
    RowId,
    Services,
    TransactionRoute,
    allow,
    computing,
)
from .approval_schemas import PreparedOut
from .approvals import SUPERVISORS, DecisionIn, EnvelopeIn
from .schemas import SchemaOf

router = APIRouter(prefix="/api", tags=["procedures"], route_class=TransactionRoute)

ProcedureJson = Annotated[dict[str, Any], SchemaOf(Procedure)]
Name = Annotated[str, Path(min_length=1, max_length=100,
                           pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.:\-]*$")]
Version = Annotated[int, Path(ge=1, le=MAX_PROCEDURE_VERSION)]


class ProcedureDecisionOut(BaseModel):
    id: int
    decision: str
    reason: str
    supervisor: str | None
    key_id: str
    procedure_digest: str
    envelope: str = Field(description="the DSSE envelope as signed, verbatim")
    created_at: datetime
    log_index: int | None
    integrity: list[str] = Field(description="how the row disagrees with its log entry or its "
                                 "own envelope; empty when it agrees")


class ProcedureSummaryOut(BaseModel):
    name: str
    version: int
    digest: str
    author: str | None
    saved_at: datetime
    approved_by: str | None = Field(description="the supervisor whose signed approval of this "
                                    "version holds, or null")
    reference: dict[str, Any] = Field(description="what a goal's refines names to use it")
    log_index: int | None
    integrity: list[str]


class ProcedureOut(ProcedureSummaryOut):
    document: ProcedureJson
    decisions: list[ProcedureDecisionOut]


class ProcedureUseOut(BaseModel):
    name: str
    version: int
    digest: str | None
    in_library: bool
    approved_by: str | None


class ProcedureUsesOut(BaseModel):
    procedures: list[ProcedureUseOut]
    all_approved: bool = Field(description="true when every procedure the orders name is a "
                               "library version a supervisor approved at the pinned digest "
                               "(also when they name none)")
    truncated: bool = Field(description="the orders name more procedure versions than are "
                            "listed (200); all_approved is then false")


def _summary(db: Db, row: ProcedureRecord) -> dict[str, Any]:
    return {"name": row.name, "version": row.version, "digest": row.digest,
            "author": _username(db, row.author_id), "saved_at": row.updated_at,
            "approved_by": service.approved_by(db, row.name, row.version, row.digest),
            "reference": {"procedure": row.name, "version": row.version, "digest": row.digest},
            "log_index": log_index_of(db, row.event_id),
            "integrity": service.procedure_integrity(db, row)}


def _decision(db: Db, approval: ProcedureApproval) -> ProcedureDecisionOut:
    return ProcedureDecisionOut(
        id=approval.id, decision=approval.decision, reason=approval.reason,
        supervisor=_username(db, approval.supervisor_id), key_id=approval.key_id,
        procedure_digest=approval.procedure_digest, envelope=approval.envelope,
        created_at=approval.created_at, log_index=log_index_of(db, approval.event_id),
        integrity=service.approval_integrity(db, approval))


@router.get("/procedures", operation_id="listProcedures",
            response_model=list[ProcedureSummaryOut], **allow(*EVERYONE))
def list_procedures(db: Db, name: Annotated[str | None, Query(max_length=100)] = None
                    ) -> list[dict[str, Any]]:
    """Saved procedure versions by name, newest version first: at most 200."""
    return [_summary(db, row) for row in service.list_procedures(db, name)]


@router.post("/procedures", operation_id="saveProcedure", status_code=201,
             response_model=ProcedureOut, **allow(*OPERATORS))
def save_procedure(body: ProcedureJson, principal: CurrentPrincipal, db: Db,
                   services: Services) -> dict[str, Any]:
    """Save a procedure version: its name's next version number, checked like a refinement
    (errors refuse it, 422). A saved version never changes (409 for the same number)."""
    # Checked in a read session before the write transaction begins (`db` is not touched
    # until then): the check takes seconds, and other writers must not wait for it.
    with services.database.session(write=False) as reader:
        checked = service.checked_procedure(reader, procedure_from_data(body))
    row = service.save_procedure(db, signer=services.signer, procedure=checked,
                                 author=principal.user)
    return {**_summary(db, row), "document": row.document, "decisions": []}


@router.get("/procedures/{name}/versions/{version}", operation_id="getProcedure",
            response_model=ProcedureOut, **allow(*EVERYONE))
def get_procedure(name: Name, version: Version, db: Db) -> dict[str, Any]:
    row = service.get_procedure(db, name, version)
    return {**_summary(db, row), "document": row.document,
            "decisions": [_decision(db, a) for a in service.decisions_of(db, name, version)]}


@router.post("/procedures/{name}/versions/{version}/statement",
             operation_id="prepareProcedureDecision", response_model=PreparedOut,
             **computing(allow(*SUPERVISORS)))
def prepare_decision(name: Name, version: Version, body: DecisionIn,
                     principal: CurrentPrincipal, db: Db, services: Services) -> dict[str, Any]:
    """The exact statement to sign about this procedure version: sign the DSSE PAE (`pae`)
    with your registered key, then POST the envelope to `/decision`. Nothing is stored."""
    return service.prepare_procedure_decision(
        db, name=name, version=version, supervisor=principal.user, decision=body.decision,
        reason=body.reason, key_id=body.key_id, signer=services.signer).to_json()


@router.post("/procedures/{name}/versions/{version}/decision",
             operation_id="signProcedureDecision", status_code=201,
             response_model=ProcedureDecisionOut, **allow(*SUPERVISORS))
def sign_decision(name: Name, version: Version, body: EnvelopeIn, principal: CurrentPrincipal,
                  db: Db, services: Services) -> ProcedureDecisionOut:
    """Verify and store a signed decision on the version (your password, entered again, is
    required); a version has at most one decision."""
    approval = service.decide_procedure(db, signer=services.signer, name=name, version=version,
                                        supervisor=principal.user, envelope=body.envelope,
                                        password=body.password)
    return _decision(db, approval)


@router.get("/missions/{mission_id}/versions/{number}/procedures",
            operation_id="getVersionProcedures", response_model=ProcedureUsesOut,
            **allow(*EVERYONE))
def version_procedures(mission_id: Annotated[str, Path(max_length=100)], number: RowId,
                       db: Db) -> ProcedureUsesOut:
    """The procedure versions this mission version uses, and whether each is approved."""
    version = get_version(db, mission_id, number)
    uses, truncated = service.procedure_uses(db, orders_from_data(version.orders))
    return ProcedureUsesOut(
        procedures=[ProcedureUseOut(name=u.name, version=u.version, digest=u.digest,
                                    in_library=u.in_library, approved_by=u.approved_by)
                    for u in uses],
        all_approved=not truncated and all(u.approved_by is not None for u in uses),
        truncated=truncated)
