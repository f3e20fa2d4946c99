"""Response models of the approvals, log and audit routes (docs/api.md, "Approvals and audit").

Bodies built as dicts are validated against these and written with `exclude_unset`, so a key
the server leaves out stays out and the JSON is what it was before the models existed."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any

from pydantic import BaseModel, Field

from ...approvals.bundle_model import Bundle
from ...approvals.bundle_model import CheckpointOut as CheckpointOut
from .campaign_schemas import CampaignRecordJson
from .rehearsal_schemas import RehearsalRecordJson
from .schemas import FindingOut, OrdersJson, PathCountsOut, ProbabilitiesJson, SchemaOf


class KeyOut(BaseModel):
    key_id: str
    public_key: str
    user: str | None
    name: str
    status: str
    created_at: datetime
    revoked_at: datetime | None


class SubmissionOut(BaseModel):
    id: int
    mission: str
    version: int
    digest: str
    state: str
    rehearsal: str | None = None
    submitted_by: str | None
    submitted_at: datetime
    decided_by: str | None
    decided_at: datetime | None
    reason: str
    integrity: list[str] = Field(default_factory=list, description=(
        "how this row disagrees with the log, which is the source of truth (empty: agrees)"))


class ApprovalOut(BaseModel):
    id: int
    mission: str
    version: int
    digest: str
    vehicle: str | None
    decision: str
    reason: str
    revokes: int | None
    operator: str | None
    supervisor: str | None
    key_id: str
    submission: int
    created_at: datetime
    log_index: int | None
    integrity: list[str] = Field(default_factory=list, description=(
        "how this row disagrees with its log entry, which is the source of truth"))


class DecisionOut(ApprovalOut):
    receipt: str | None = Field(description="the log signer's signed receipt for the "
                                "decision's log entry (entry hash, index, time)")


class ApprovalPage(BaseModel):
    items: list[ApprovalOut]
    next_cursor: int | None


class PreviousApprovalOut(BaseModel):
    """The version approved before this one, for the review's diff."""

    version: int
    digest: str
    approval: int
    state: str
    orders: OrdersJson


class ReviewOut(BaseModel):
    """What a review shows of one version (GET .../versions/{number}/review)."""

    mission: str
    version: int
    digest: str
    author: str | None
    created_at: str
    orders: OrdersJson
    plain: str
    rules: list[str] = Field(description="the contingency rules, one plain-language sentence "
                             "each (empty when none or unreadable)")
    ok: bool
    findings: list[FindingOut]
    paths: PathCountsOut | None
    checker: str = Field(description="the fingerprint of the checks that made these findings; "
                         "a statement to sign names it")
    probabilities: ProbabilitiesJson | None = Field(
        default=None, description="outcome probabilities: terminals, violation, "
        "expected energy and time, min/max where probabilities are intervals or missing; "
        "absent when the orders declare none")
    submissions: list[SubmissionOut]
    previous: PreviousApprovalOut | None
    may_submit: bool
    submit_refusal: str | None
    may_decide: bool
    decide_refusal: str | None


class StatementSubject(BaseModel):
    name: str
    digest: dict[str, str]


class Statement(BaseModel):
    """An in-toto statement whose predicate is the countersign approval predicate."""

    type_: str = Field(alias="_type")
    subject: list[StatementSubject]
    predicateType: str
    predicate: dict[str, Any]


# Passed through: a prepared statement keeps its build order, a signed one its canonical order.
StatementJson = Annotated[dict[str, Any], SchemaOf(Statement)]


class PreparedOut(BaseModel):
    """The statement to sign: sign `pae` (which must equal PAE(payloadType, payload))."""

    payloadType: str
    payload: str
    pae: str
    statement: StatementJson


class CosignedCheckpointOut(CheckpointOut):
    cosignatures: list[str]


class CosignatureOut(BaseModel):
    size: int
    witness: str
    cosignature: str


class InclusionProofOut(BaseModel):
    index: int
    size: int
    leaf_hash: str
    root: str
    hashes: list[str]


class ConsistencyProofOut(BaseModel):
    first: int
    second: int
    first_root: str
    second_root: str
    hashes: list[str]


class LogEntryOut(BaseModel):
    index: int
    leaf_hash: str
    entry: str
    receipt: str | None


class CitedRehearsalOut(BaseModel):
    digest: str
    mission: str
    version: int | None
    orders_digest: str
    source: str
    owner: str | None
    created_at: str
    replay_digest: str
    replay: str
    record: RehearsalRecordJson


class ApprovalDetailOut(ApprovalOut):
    """An approval as signed (GET /api/approvals/{id})."""

    envelope: str
    statement: StatementJson
    orders: OrdersJson
    plain: str
    rules: list[str]
    findings: list[FindingOut]
    paths: PathCountsOut | None
    rehearsal: CitedRehearsalOut | None
    key: KeyOut
    checkpoint: CheckpointOut
    inclusion: InclusionProofOut | None


class BundleOut(Bundle):
    """An audit bundle for `countersign audit verify BUNDLE` (DESIGN.md, approval record)."""

    # Documented by the orders' and the records' models; passed through as stored.
    orders: dict[str, OrdersJson]
    rehearsals: dict[str, RehearsalRecordJson]
    campaigns: dict[str, CampaignRecordJson] = Field(default={})
