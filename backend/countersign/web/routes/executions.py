"""Execution logs of an approved version: checked against its orders, recorded in the log; and
what a record (approval) page shows of them and of its rehearsal, checked by the same checker."""

from __future__ import annotations

import base64
import binascii
from datetime import UTC, datetime
from typing import Any, Literal

from fastapi import APIRouter, Request
from pydantic import BaseModel, Field, model_validator

from ...errors import Unprocessable
from ...export.execution_input import ExecutionInputError, to_execution_log
from ...export.rehearsal_log import RehearsalRecordError, RehearsalRun, rehearsal_runs
from ...limits import CLOCK_SKEW
from ...orders.model import Orders
from ...orders.reader import orders_from_data
from ...rehearse.execution import ExecutionLogError, ExecutionVerdict, check_execution, read_log
from ...rehearse.execution_evidence import TimeWindow
from ...store import approvals as approvals_service
from ...store.db import Database
from ...store.executions import approved_orders, record_execution, recorded_executions
from ...store.rehearsals import get_record
from ...store.tables import MissionVersion, Submission
from ..deps import LOG_READERS, CurrentPrincipal, Db, RowId, Services, TransactionRoute, allow
from .schemas import RequestBody

router = APIRouter(prefix="/api", tags=["executions"], route_class=TransactionRoute)
EXECUTION_ROLES = ("operator", "supervisor")
MAX_LOG_CHARS = 4 * 1024 * 1024


class ExecutionIn(RequestBody):
    log: str | None = Field(default=None, max_length=MAX_LOG_CHARS,
                            description="NDJSON, one line per goal run: goal, outcome, time, "
                            "start, readings; or a MOOS alog (text)")
    data_base64: str | None = Field(
        default=None, max_length=MAX_LOG_CHARS * 4 // 3 + 4,
        description="a binary vehicle log, base64: IMC messages (PlanControlState ...)")
    format: Literal["auto", "ndjson", "imc", "alog"] = Field(
        default="auto", description="the log's format (auto: detected)")

    @model_validator(mode="after")
    def _one_log(self) -> ExecutionIn:
        if (self.log is None) == (self.data_base64 is None):
            raise ValueError("give the log as `log` (text) or `data_base64`, not both")
        return self


class DeviationOut(BaseModel):
    code: str
    step: int
    message: str


class UsageOut(BaseModel):
    quantity: str
    used: float
    budget: float | None
    source: str = Field(description="readings, timestamps or model")
    over: bool
    lower_bound: bool


Status = Literal["no-deviation", "deviation", "unverified"]
STATUS_HELP = ("no-deviation (followed the orders, with times and readings for every "
               "constraint in scope), deviation, or unverified (no deviation found, but "
               "evidence missing: see evidence.gaps)")


class EvidenceOut(BaseModel):
    complete: bool
    timed: bool = Field(description="every goal run has start and end times")
    untimed_steps: list[int]
    constraints_read: list[str] = Field(
        description="constraints in scope read at every goal run they apply to")
    constraints_unread: list[str]
    gaps: list[str] = Field(description='what is missing, e.g. "no readings for C1, C4"')


class ExecutionOut(BaseModel):
    ok: bool = Field(description="no deviation, and the evidence to say so")
    status: Status = Field(description=STATUS_HELP)
    evidence: EvidenceOut
    path: int | None
    terminal: str | None
    summary: str
    deviations: list[DeviationOut]
    usage: list[UsageOut] = Field(default_factory=list)
    format: str = Field(default="ndjson", description="the format the log was read as")
    notes: list[str] = Field(default_factory=list,
                             description="what converting a vehicle log had to assume")
    log_index: int | None = Field(description="the execution.recorded entry in the audit log")


class RecordedExecutionOut(BaseModel):
    log_index: int
    at: str | None
    actor: str | None = Field(description="who uploaded the log")
    ok: bool
    status: Status = Field(description=STATUS_HELP)
    evidence: EvidenceOut | None = Field(
        description="what the log evidenced (null: recorded before evidence was checked)")
    path: int | None
    terminal: str | None
    summary: str
    deviations: list[DeviationOut]
    statement: str = Field(description='e.g. "approved, executed as path 17, no deviation"')


class RehearsalRunOut(BaseModel):
    claimed_path: int | None = Field(description="the path number the rehearsal reported")
    vehicle: str | None = Field(
        default=None, description="a team's rehearsal: the member whose run this is, checked "
        "against that member's orders")
    verdict: ExecutionOut


class RecordExecutionsOut(BaseModel):
    decision: str
    executions: list[RecordedExecutionOut]
    rehearsal: list[RehearsalRunOut] | None = Field(
        description="the cited rehearsal's runs through the execution checker (null: none)")


def _input_bytes(body: ExecutionIn) -> bytes:
    if body.log is not None:
        return body.log.encode()
    try:
        return base64.b64decode(body.data_base64 or "", validate=True)
    except (binascii.Error, ValueError):
        raise Unprocessable("data_base64 is not base64") from None


def _out(verdict: ExecutionVerdict, **extra: Any) -> ExecutionOut:
    return ExecutionOut(ok=verdict.ok, status=verdict.status,
                        evidence=EvidenceOut(**verdict.evidence.to_json()),
                        path=verdict.path, terminal=verdict.terminal, summary=verdict.summary(),
                        deviations=[DeviationOut(**d.to_json()) for d in verdict.deviations],
                        usage=[UsageOut(**u.to_json()) for u in verdict.usage], **extra)


@router.post("/missions/{mission_id}/versions/{number}/executions",
             operation_id="recordExecution", response_model=ExecutionOut, status_code=201,
             **allow(*EXECUTION_ROLES))
def post_execution(mission_id: str, number: RowId, body: ExecutionIn, request: Request,
                   principal: CurrentPrincipal, db: Db, services: Services) -> ExecutionOut:
    """Check an execution log (NDJSON, IMC PlanControlState messages or a MOOS alog) against
    the version's approved orders and append the verdict to the log (execution.recorded)."""
    data = _input_bytes(body)
    # Reading and checking happen before the write transaction begins (`db` is not touched
    # until the verdict is recorded): a slow check must not hold the write lock.
    database: Database = request.app.state.database
    with database.session(write=False) as reader:
        checked = approved_orders(reader, mission_id=mission_id, number=number)
    window = TimeWindow.of(now=datetime.now(UTC), skew_s=CLOCK_SKEW.total_seconds(),
                           not_before=checked.approved_at)
    try:
        result = to_execution_log(checked.orders, data, body.format)
        verdict = check_execution(checked.orders, read_log(result.ndjson), window)
    except (ExecutionLogError, ExecutionInputError) as exc:
        raise Unprocessable(str(exc)) from None
    index = record_execution(
        db, mission_id=mission_id, number=number, log=data, actor=principal.user,
        checked=checked, verdict=verdict,
        source={"format": result.fmt, "notes": list(result.notes)}, signer=services.signer)
    return _out(verdict, log_index=index, format=result.fmt, notes=list(result.notes))


def _status(verdict: dict[str, Any]) -> str:
    # Entries recorded before evidence was checked say only ok; they claimed no deviation
    # without the evidence now required, so they are not shown as one.
    if "status" in verdict:
        return str(verdict["status"])
    return "deviation" if verdict.get("deviations") or not verdict.get("ok") else "unverified"


def statement_of(decision: str, verdict: dict[str, Any]) -> str:
    """What the record page says of one execution."""
    status = _status(verdict)
    if status == "no-deviation":
        return f"{decision}, executed as path {verdict.get('path')}, no deviation"
    if status == "unverified":
        gaps = (verdict.get("evidence") or {}).get("gaps") or [
            "recorded before times and readings were required"]
        return (f"{decision}, executed as path {verdict.get('path')}, unverified: "
                f"{'; '.join(str(g) for g in gaps)}")
    deviations = verdict.get("deviations") or []
    named = "; ".join(f"{d.get('code')} at step {d.get('step')}: {d.get('message')}"
                      for d in deviations[:5])
    more = f" (and {len(deviations) - 5} more)" if len(deviations) > 5 else ""
    return f"{decision}, executed with {len(deviations)} deviation(s): {named}{more}"


@router.get("/approvals/{approval_id}/executions", operation_id="getRecordExecutions",
            response_model=RecordExecutionsOut, **allow(*LOG_READERS))
def get_record_executions(approval_id: RowId, db: Db) -> RecordExecutionsOut:
    """The recorded executions of the approval's version, each as the record page states it,
    and the cited rehearsal's runs checked by the same execution checker."""
    approval = approvals_service.get_approval(db, approval_id)
    version = db.get_one(MissionVersion, approval.version_id)
    executions = [
        RecordedExecutionOut(
            log_index=e["log_index"], at=e.get("at"), actor=e.get("actor"),
            ok=_status(e) == "no-deviation", status=_status(e),
            evidence=EvidenceOut(**e["evidence"]) if e.get("evidence") else None,
            path=e.get("path"), terminal=e.get("terminal"),
            summary=str(e.get("summary", "")),
            deviations=[DeviationOut(**d) for d in e.get("deviations") or []],
            statement=statement_of(approval.decision, e))
        for e in recorded_executions(db, mission_id=version.mission_id, number=version.number)]
    rehearsal = None
    digest = db.get_one(Submission, approval.submission_id).rehearsal_digest
    if digest is not None:
        orders = orders_from_data(version.orders)
        record = dict(get_record(db, digest).record)
        # A team's record holds each member's runs: each is checked against its own orders.
        members = [(m.vehicle, m.orders) for m in orders.team] if orders.team else [
            (None, orders)]
        rehearsal = [RehearsalRunOut(claimed_path=run.claimed_path, vehicle=vehicle,
                                     verdict=_rehearsal_verdict(member_orders, run.ndjson))
                     for vehicle, member_orders in members
                     for run in _member_runs(record, vehicle)]
    return RecordExecutionsOut(decision=approval.decision, executions=executions,
                               rehearsal=rehearsal)


def _member_runs(record: dict[str, Any], vehicle: str | None) -> list[RehearsalRun]:
    """The member's runs; none when the record does not hold that member (a record made
    before members carried their runs, which the verdicts then leave out)."""
    try:
        return rehearsal_runs(record, vehicle)
    except RehearsalRecordError:
        return []


def _rehearsal_verdict(orders: Orders, ndjson: str) -> ExecutionOut:
    try:
        return _out(check_execution(orders, read_log(ndjson)), log_index=None,
                    format="rehearsal")
    except ExecutionLogError as exc:
        return ExecutionOut(ok=False, status="unverified", evidence=EvidenceOut(
            complete=False, timed=False, untimed_steps=[], constraints_read=[],
            constraints_unread=[], gaps=[str(exc)]), path=None, terminal=None, summary=str(exc),
            deviations=[], log_index=None, format="rehearsal")
