"""Submissions and reviews as the API shows them.

The store records submissions and decisions; this module gathers what a route answers about
them (plain data: dicts of the response fields), with the report service passed in."""

from __future__ import annotations

import json
from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import defer

from ..approvals import dsse
from ..approvals.signer import LogSigner
from ..orders.reader import orders_from_data
from ..orders.writers import write
from ..rules.plain_orders import rules_sentences
from ..store import approvals as store
from ..store.integrity import submissions_checked
from ..store.missions import get_version, report_for
from ..store.rehearsals import get_record, record_summary
from ..store.report_service import ReportService
from ..store.tables import MissionVersion, SigningKey, Submission, User


def submissions_fields(db: DbSession, submissions: list[Submission]) -> list[dict[str, Any]]:
    """The fields of each submission (its version, who submitted and decided it, and its state
    as the log tells it), read with a fixed number of queries whatever their number."""
    version_ids = {s.version_id for s in submissions}
    versions = {v.id: v for v in db.scalars(
        select(MissionVersion).options(defer(MissionVersion.orders))
        .where(MissionVersion.id.in_(version_ids)))} if version_ids else {}
    user_ids = {i for s in submissions for i in (s.submitted_by, s.decided_by) if i is not None}
    names: dict[int, str] = dict(db.execute(
        select(User.id, User.username).where(User.id.in_(user_ids))).all()) if user_ids else {}
    checked = submissions_checked(db, submissions)
    out = []
    for submission in submissions:
        version = versions[submission.version_id]
        state, integrity = checked[submission.id]
        out.append({
            "id": submission.id, "mission": version.mission_id, "version": version.number,
            "digest": version.digest, "state": state,
            "submitted_by": names.get(submission.submitted_by)
            if submission.submitted_by is not None else None,
            "submitted_at": submission.submitted_at,
            "decided_by": names.get(submission.decided_by)
            if submission.decided_by is not None else None,
            "decided_at": submission.decided_at, "reason": submission.reason,
            "rehearsal": submission.rehearsal_digest, "integrity": integrity})
    return out


def submission_fields(db: DbSession, submission_id: int) -> dict[str, Any]:
    """The fields of one submission (NotFound when there is none)."""
    return submissions_fields(db, [store.get_submission(db, submission_id)])[0]


def list_submissions(db: DbSession, *, state: str | None, mission: str | None,
                     limit: int) -> list[dict[str, Any]]:
    """The latest submissions first, optionally of one state or one mission."""
    query = select(Submission).order_by(Submission.id.desc()).limit(limit)
    if state:
        query = query.where(Submission.state == state)
    if mission:
        query = query.join(MissionVersion, MissionVersion.id == Submission.version_id).where(
            MissionVersion.mission_id == mission)
    return submissions_fields(db, list(db.scalars(query)))


def review(db: DbSession, *, reports: ReportService, user: User, mission_id: str,
           number: int, signer: LogSigner | None) -> dict[str, Any]:
    """What a review shows of one version (see the reviewVersion route); `submissions` holds
    each submission's fields (submissions_fields)."""
    version = get_version(db, mission_id, number)
    orders = orders_from_data(version.orders)
    report = report_for(db, orders, version.digest, reports=reports).report
    submissions = list(db.scalars(select(Submission).where(Submission.version_id == version.id)
                                  .order_by(Submission.id.desc())))
    current = submissions[0] if submissions else None
    refused = store.submit_refusal(user=user, number=number, report=report, active=current)
    submit_refusal = str(refused) if refused is not None else None
    decide_refusal = store.decision_refusal(db, user=user, version=version,
                                            submission=current, signer=signer)
    previous = store.previous_approval(db, version)
    previous_out = None
    if previous is not None:
        before = db.get_one(MissionVersion, previous.version_id)
        state = db.get_one(Submission, previous.submission_id).state
        previous_out = {"version": before.number, "digest": before.digest,
                        "approval": previous.id, "state": state, "orders": before.orders}
    author = db.get(User, version.author_id)
    return {
        "mission": mission_id, "version": number, "digest": version.digest,
        "author": author.username if author else None,
        "created_at": version.created_at.isoformat(), "orders": version.orders,
        "plain": write(orders, "plain"), "rules": rules_sentences(orders),
        "ok": report["ok"], "findings": report["findings"],
        "paths": report.get("paths"), "checker": report["checker"],
        "probabilities": report.get("probabilities"),
        "submissions": submissions_fields(db, submissions),
        "previous": previous_out,
        "may_submit": submit_refusal is None, "submit_refusal": submit_refusal,
        "may_decide": decide_refusal is None, "decide_refusal": decide_refusal,
    }


def key_fields(db: DbSession, key: SigningKey) -> dict[str, Any]:
    user = db.get(User, key.user_id)
    return {"key_id": key.id, "public_key": key.public_key,
            "user": user.username if user else None, "name": key.name,
            "status": store.key_status(db, key), "created_at": key.created_at,
            "revoked_at": key.revoked_at}


def approval_detail(db: DbSession, *, approval_id: int, reports: ReportService,
                    signer: LogSigner) -> dict[str, Any]:
    """An approval as signed: envelope, statement, the orders as approved, plain-language
    orders and contingency rules, findings, path summary, its `summary` as the list shows it,
    the `key` that signed it, and an inclusion proof against the latest checkpoint."""
    approval = store.get_approval(db, approval_id)
    version = db.get_one(MissionVersion, approval.version_id)
    orders = orders_from_data(version.orders)
    report = report_for(db, orders, version.digest, reports=reports).report
    checkpoint = store.latest_checkpoint(db, signer=signer)
    summary = store.approval_summary(db, approval)
    envelope = dsse.parse_envelope(approval.envelope)
    payload = dsse.unb64(envelope["payload"], "the payload")
    proof = None
    if summary["log_index"] is not None and summary["log_index"] < checkpoint.tree_size:
        proof = store.inclusion_proof(db, index=summary["log_index"], size=checkpoint.tree_size)
    return {
        "summary": summary,
        "envelope": approval.envelope,
        "statement": json.loads(payload),
        "orders": version.orders,
        "plain": write(orders, "plain"),
        "rules": rules_sentences(orders),
        "findings": report["findings"],
        "paths": report.get("paths"),
        "rehearsal": _cited_rehearsal(db, approval.submission_id),
        "key": key_fields(db, db.get_one(SigningKey, approval.key_id)),
        "checkpoint": store.checkpoint_json(checkpoint),
        "inclusion": proof,
    }


def _cited_rehearsal(db: DbSession, submission_id: int) -> dict[str, Any] | None:
    digest = db.get_one(Submission, submission_id).rehearsal_digest
    if digest is None:
        return None
    row = get_record(db, digest)
    return {**record_summary(db, row), "created_at": row.created_at.isoformat(),
            "record": row.record}
