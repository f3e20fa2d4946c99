"""Submission, review and signing, supervisor keys, the transparency log and the audit API."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Path, Query, Request
from fastapi.responses import JSONResponse
from pydantic import Field
from sqlalchemy import select

from ...approvals.signer import LogSigner
from ...limits import MAX_REASON
from ...services import approvals
from ...store import approvals as service
from ...store.log_gaps import LogEntriesMissing
from ...store.rehearsals import attach
from ...store.tables import Approval, SigningKey
from ..deps import (
    EVERYONE,
    LOG_READERS,
    OPERATORS,
    CurrentPrincipal,
    Db,
    RowId,
    Services,
    TransactionRoute,
    allow,
    computing,
)
from ..problems import problem
from .approval_schemas import (
    ApprovalDetailOut,
    ApprovalOut,
    ApprovalPage,
    BundleOut,
    CheckpointOut,
    ConsistencyProofOut,
    DecisionOut,
    InclusionProofOut,
    KeyOut,
    LogEntryOut,
    PreparedOut,
    ReviewOut,
    SubmissionOut,
)
from .instants import Instant
from .schemas import RequestBody

router = APIRouter(prefix="/api", tags=["approvals"], route_class=TransactionRoute)
SUPERVISORS = ("supervisor",)
KEY_READERS = ("supervisor", "auditor", "admin")
# Bodies built as dicts: a key the dict leaves out (a finding's `details`) stays out.
AS_BUILT: dict[str, Any] = {"response_model_exclude_unset": True}


def get_signer(services: Services) -> LogSigner:
    """The log signer the app opened at start (services/log_signer.py): its key is a file of its
    own, outside the database."""
    return services.signer


Signer = Annotated[LogSigner, Depends(get_signer)]


class KeyIn(RequestBody):
    public_key: str = Field(min_length=1, max_length=200,
                            description="standard base64 of the raw 32-byte Ed25519 public key")
    name: str = Field(default="", max_length=100)
    password: str = Field(min_length=1, max_length=1024, description="fresh confirmation")


class KeyRevokeIn(RequestBody):
    password: str = Field(min_length=1, max_length=1024)
    reason: str = Field(default="", max_length=MAX_REASON)


class DecisionIn(RequestBody):
    decision: str = Field(pattern="^(approved|rejected)$")
    reason: str = Field(default="", max_length=MAX_REASON)
    key_id: str = Field(min_length=1, max_length=64)


class RevocationIn(RequestBody):
    reason: str = Field(min_length=1, max_length=MAX_REASON)
    key_id: str = Field(min_length=1, max_length=64)


class EnvelopeIn(RequestBody):
    envelope: str = Field(min_length=2, max_length=200_000,
                          description="the DSSE envelope as JSON text, stored verbatim")
    password: str | None = Field(
        default=None, max_length=1024,
        description="the signer's password, entered again for this decision: checked by the "
        "server (argon2) in this request and counted against the sign-in throttle; without "
        "it, or wrong, the decision is refused (403) even when validly signed")


class SubmitIn(RequestBody):
    rehearsal: str | None = Field(default=None, pattern=r"^sha256:[0-9a-f]{64}$",
                                  description="digest of a stored rehearsal record of this "
                                  "exact version, cited by the approval statement")


class AttachIn(RequestBody):
    rehearsal: str = Field(pattern=r"^sha256:[0-9a-f]{64}$")


def _key_out(db: Db, key: SigningKey) -> KeyOut:
    return KeyOut(**approvals.key_fields(db, key))


def _submission_out(db: Db, submission_id: int) -> SubmissionOut:
    return SubmissionOut(**approvals.submission_fields(db, submission_id))


# --- keys -----------------------------------------------------------------------------------

@router.get("/keys", operation_id="listKeys", response_model=list[KeyOut],
            **allow(*KEY_READERS))
def list_keys(db: Db) -> list[KeyOut]:
    return [_key_out(db, k) for k in db.scalars(select(SigningKey).order_by(SigningKey.created_at))]


@router.post("/keys", operation_id="registerKey", status_code=201, response_model=KeyOut,
             **allow(*SUPERVISORS))
def register_key(body: KeyIn, principal: CurrentPrincipal, db: Db, services: Services) -> KeyOut:
    key = service.register_key(db, user=principal.user, public_key=body.public_key,
                               name=body.name, password=body.password, signer=services.signer)
    return _key_out(db, key)


@router.post("/keys/{key_id}/revoke", operation_id="revokeKey", response_model=KeyOut,
             **allow("supervisor", "admin"))
def revoke_key(key_id: Annotated[str, Path(max_length=64)], body: KeyRevokeIn,
               principal: CurrentPrincipal, db: Db, services: Services) -> KeyOut:
    key = service.revoke_key(db, user=principal.user, key_id=key_id, password=body.password,
                             reason=body.reason, signer=services.signer)
    return _key_out(db, key)


# --- workflow -------------------------------------------------------------------------------

@router.post("/missions/{mission_id}/versions/{number}/submit", operation_id="submitVersion",
             status_code=201, response_model=SubmissionOut, **allow(*OPERATORS))
def submit_version(mission_id: str, number: RowId, principal: CurrentPrincipal,
                   db: Db, services: Services, body: SubmitIn | None = None) -> SubmissionOut:
    submission = service.submit(db, signer=services.signer, mission_id=mission_id, number=number,
                                operator=principal.user, reports=services.reports,
                                rehearsal=body.rehearsal if body else None)
    return _submission_out(db, submission.id)


@router.post("/submissions/{submission_id}/rehearsal", operation_id="attachRehearsal",
             response_model=SubmissionOut, **allow(*OPERATORS))
def attach_rehearsal(submission_id: RowId, body: AttachIn, principal: CurrentPrincipal,
                     db: Db, services: Services) -> SubmissionOut:
    """Cite a stored rehearsal record of exactly the submitted version (409 otherwise);
    only the submitting operator, only while the submission awaits a decision."""
    submission = service.get_submission(db, submission_id)
    if submission.submitted_by != principal.user.id:
        raise service.Refused("only the operator who submitted it can attach a rehearsal")
    attach(db, submission=submission, digest=body.rehearsal, actor=principal.user,
           signer=services.signer)
    return _submission_out(db, submission_id)


@router.get("/submissions", operation_id="listSubmissions", response_model=list[SubmissionOut],
            **allow(*EVERYONE))
def list_submissions(
    db: Db,
    state: Annotated[str | None, Query(max_length=16)] = None,
    mission: Annotated[str | None, Query(max_length=100)] = None,
    limit: Annotated[int, Query(ge=1, le=500)] = 100,
) -> list[SubmissionOut]:
    return [SubmissionOut(**fields) for fields in approvals.list_submissions(
        db, state=state, mission=mission, limit=limit)]


@router.get("/submissions/{submission_id}", operation_id="getSubmission",
            response_model=SubmissionOut, **allow(*EVERYONE))
def get_submission(submission_id: RowId, db: Db) -> SubmissionOut:
    return _submission_out(db, submission_id)


@router.post("/submissions/{submission_id}/withdraw", operation_id="withdrawSubmission",
             response_model=SubmissionOut, **allow(*OPERATORS))
def withdraw_submission(submission_id: RowId, principal: CurrentPrincipal,
                        db: Db, services: Services) -> SubmissionOut:
    service.withdraw(db, submission_id=submission_id, operator=principal.user,
                     signer=services.signer)
    return _submission_out(db, submission_id)


@router.get("/missions/{mission_id}/versions/{number}/review", operation_id="reviewVersion",
            response_model=ReviewOut, **AS_BUILT, **allow(*EVERYONE))
def review_version(mission_id: str, number: RowId, principal: CurrentPrincipal,
                   db: Db, services: Services) -> dict[str, Any]:
    """What a review shows of one version: its orders, plain-language orders, contingency
    `rules` (one sentence each; empty when none or unreadable), findings, path summary (the
    paths themselves page from `GET /missions/{id}/paths?version=`), its submissions, the
    previously approved version's orders (for the diff), and whether the caller may submit it
    or sign a decision on it (and why not)."""
    review = approvals.review(db, reports=services.reports, user=principal.user,
                              mission_id=mission_id, number=number, signer=services.signer)
    return {**review, "submissions": [SubmissionOut(**fields).model_dump(mode="json")
                                      for fields in review["submissions"]]}


@router.post("/submissions/{submission_id}/statement", operation_id="prepareDecision",
             response_model=PreparedOut, **computing(allow(*SUPERVISORS)))
def prepare_decision(submission_id: RowId, body: DecisionIn, principal: CurrentPrincipal,
                     db: Db, services: Services) -> dict[str, Any]:
    """The exact in-toto statement to sign: sign the DSSE PAE bytes (`pae`, base64) with the
    registered key, then POST the envelope to `/decision`. Nothing is stored."""
    return service.prepare_decision(db, submission_id=submission_id, supervisor=principal.user,
                                    decision=body.decision, reason=body.reason,
                                    key_id=body.key_id, reports=services.reports,
                                    signer=services.signer).to_json()


@router.post("/submissions/{submission_id}/decision", operation_id="signDecision",
             status_code=201, response_model=DecisionOut, **allow(*SUPERVISORS))
def sign_decision(submission_id: RowId, body: EnvelopeIn, principal: CurrentPrincipal,
                  db: Db, services: Services) -> DecisionOut:
    approval = service.decide(db, submission_id=submission_id, supervisor=principal.user,
                              envelope=body.envelope, password=body.password,
                              reports=services.reports, signer=services.signer)
    return DecisionOut(**service.approval_summary(db, approval),
                       receipt=service.receipt_of(db, approval))


@router.post("/approvals/{approval_id}/statement", operation_id="prepareRevocation",
             response_model=PreparedOut, **computing(allow(*SUPERVISORS)))
def prepare_revocation(approval_id: RowId, body: RevocationIn, principal: CurrentPrincipal,
                       db: Db, services: Services) -> dict[str, Any]:
    return service.prepare_revocation(db, approval_id=approval_id, supervisor=principal.user,
                                      reason=body.reason, key_id=body.key_id,
                                      reports=services.reports, signer=services.signer).to_json()


@router.post("/approvals/{approval_id}/revoke", operation_id="revokeApproval",
             status_code=201, response_model=DecisionOut, **allow(*SUPERVISORS))
def revoke_approval(approval_id: RowId, body: EnvelopeIn, principal: CurrentPrincipal,
                    db: Db, services: Services) -> DecisionOut:
    approval = service.revoke(db, approval_id=approval_id, supervisor=principal.user,
                              envelope=body.envelope, password=body.password,
                              reports=services.reports, signer=services.signer)
    return DecisionOut(**service.approval_summary(db, approval),
                       receipt=service.receipt_of(db, approval))


# --- audit ----------------------------------------------------------------------------------

@router.get("/approvals", operation_id="listApprovals", response_model=ApprovalPage,
            **allow(*LOG_READERS))
def list_approvals(
    db: Db,
    mission: Annotated[str | None, Query(max_length=100)] = None,
    operator: Annotated[str | None, Query(max_length=64)] = None,
    supervisor: Annotated[str | None, Query(max_length=64)] = None,
    vehicle: Annotated[str | None, Query(max_length=100)] = None,
    decision: Annotated[str | None, Query(pattern="^(approved|rejected|revoked)$")] = None,
    since: Instant | None = None,
    until: Instant | None = None,
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    cursor: Annotated[int | None, Query(ge=1, le=2**31 - 1)] = None,
) -> ApprovalPage:
    """The approval history, newest first; `cursor` is the `next_cursor` of the last page."""
    filters = service.Filters(mission=mission, operator=operator, supervisor=supervisor,
                              vehicle=vehicle, decision=decision, since=since, until=until)
    query = service.approvals_query(filters).limit(limit + 1)
    if cursor:
        query = query.where(Approval.id < cursor)
    rows = list(db.scalars(query))
    items = [ApprovalOut(**summary) for summary in service.approval_summaries(db, rows[:limit])]
    return ApprovalPage(items=items, next_cursor=rows[limit - 1].id if len(rows) > limit else None)


@router.get("/approvals/{approval_id}", operation_id="getApproval",
            response_model=ApprovalDetailOut, **AS_BUILT, **allow(*LOG_READERS))
def get_approval(approval_id: RowId, db: Db, services: Services) -> dict[str, Any]:
    """An approval as signed: envelope, statement, the orders as approved, plain-language
    orders and contingency rules, findings, path summary, the key, and an inclusion proof
    against a checkpoint."""
    detail = approvals.approval_detail(db, approval_id=approval_id, reports=services.reports,
                                       signer=services.signer)
    summary = ApprovalOut(**detail.pop("summary")).model_dump(mode="json")
    return {**summary, **detail, "key": KeyOut(**detail["key"]).model_dump(mode="json")}


@router.get("/log/checkpoint", operation_id="getCheckpoint",
            response_model=CheckpointOut, **allow(*EVERYONE))
def get_checkpoint(db: Db, signer: Signer) -> dict[str, Any]:
    """The latest signed checkpoint (tree size and RFC 6962 root), signed anew when the log
    has grown since the last one."""
    return service.checkpoint_json(service.latest_checkpoint(db, signer=signer))


@router.get("/log/entries", operation_id="listLogEntries",
            response_model=list[LogEntryOut], **allow(*LOG_READERS))
def list_log_entries(
    db: Db, start: Annotated[int, Query(ge=0, le=2**62)] = 0,
    limit: Annotated[int, Query(ge=1, le=5000)] = 1000,
) -> list[dict[str, Any]]:
    return service.entries(db, start=start, limit=limit)


@router.get("/log/inclusion", operation_id="getInclusionProof",
            response_model=InclusionProofOut, **allow(*LOG_READERS))
def get_inclusion_proof(
    db: Db, index: Annotated[int, Query(ge=0, le=2**62)],
    size: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> dict[str, Any]:
    return service.inclusion_proof(db, index=index, size=size)


@router.get("/log/consistency", operation_id="getConsistencyProof",
            response_model=ConsistencyProofOut, **allow(*LOG_READERS))
def get_consistency_proof(
    db: Db, first: Annotated[int, Query(ge=1, le=2**62)],
    second: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> dict[str, Any]:
    return service.consistency_proof(db, first=first, second=second)


@router.get("/audit/bundle", operation_id="exportBundle",
            response_model=BundleOut, **AS_BUILT, **allow(*LOG_READERS))
def export_bundle(request: Request, db: Db, signer: Signer,
                  mission: Annotated[str | None, Query(max_length=100)] = None
                  ) -> dict[str, Any] | JSONResponse:
    """An audit bundle for `countersign audit verify BUNDLE` (offline). A log with entries
    deleted behind the app's back is a 409 problem naming them, whose `bundle` member holds
    what remains."""
    try:
        return service.build_bundle(db, signer=signer, mission=mission)
    except LogEntriesMissing as exc:
        return problem(409, str(exc), request, **exc.extra())
