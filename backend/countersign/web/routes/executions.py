"""Execution logs of an approved version: checked against its orders, recorded in the log."""

from __future__ import annotations

from fastapi import APIRouter, HTTPException
from pydantic import BaseModel, Field

from ...orders.model import Orders
from ...rehearse.execution import ExecutionLogError, ExecutionVerdict, check_execution, read_log
from ...store.executions import record_execution
from ..deps import CurrentPrincipal, Db, RowId, TransactionRoute, allow
from .schemas import RequestBody

router = APIRouter(prefix="/api", tags=["executions"], route_class=TransactionRoute)
EXECUTION_ROLES = ("operator", "supervisor")


class ExecutionIn(RequestBody):
    log: str = Field(max_length=4 * 1024 * 1024,
                     description="NDJSON, one line per goal run: goal, outcome, time, readings")


class DeviationOut(BaseModel):
    code: str
    step: int
    message: str


class ExecutionOut(BaseModel):
    ok: bool
    path: int | None
    terminal: str | None
    summary: str
    deviations: list[DeviationOut]
    log_index: int | None = Field(description="the execution.recorded entry in the audit log")


def _check(orders: Orders, log: str) -> ExecutionVerdict:
    return check_execution(orders, read_log(log))


@router.post("/missions/{mission_id}/versions/{number}/executions",
             operation_id="recordExecution", response_model=ExecutionOut, status_code=201,
             **allow(*EXECUTION_ROLES))
def post_execution(mission_id: str, number: RowId, body: ExecutionIn,
                   principal: CurrentPrincipal, db: Db) -> ExecutionOut:
    try:
        verdict, index = record_execution(db, mission_id=mission_id, number=number,
                                          log=body.log, actor=principal.user,
                                          check=_check)
    except ExecutionLogError as exc:
        raise HTTPException(422, str(exc)) from None
    return ExecutionOut(ok=verdict.ok, path=verdict.path, terminal=verdict.terminal,
                        summary=verdict.summary(),
                        deviations=[DeviationOut(**d.to_json()) for d in verdict.deviations],
                        log_index=index)
