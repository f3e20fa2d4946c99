"""Gathers one version's approval document (approvals/document.py) from the store: its report,
the submission's rehearsal record, and the latest decision with its signer and key."""

from __future__ import annotations

from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.document import Decision, Section, approval_document
from ..orders.reader import orders_from_data
from .approvals.log import log_index_of
from .missions import get_version, report_for
from .rehearsals import get_record, record_summary
from .report_service import ReportService
from .tables import Approval, MissionVersion, SigningKey, Submission, User


def _decision(db: DbSession, version: MissionVersion) -> tuple[Decision | None, Submission | None]:
    approvals = list(db.scalars(select(Approval).where(Approval.version_id == version.id)
                                .order_by(Approval.id.desc())))
    decided = next((a for a in approvals if a.decision in ("approved", "rejected")), None)
    latest = db.scalars(select(Submission).where(Submission.version_id == version.id)
                        .order_by(Submission.id.desc())).first()
    if decided is None:
        return None, latest
    revoked = next((a for a in approvals if a.decision == "revoked"
                    and a.revokes == decided.id), None)
    supervisor = db.get(User, decided.supervisor_id)
    key = db.get_one(SigningKey, decided.key_id)
    return Decision(
        approval=decided.id, decision=decided.decision, reason=decided.reason,
        supervisor=supervisor.username if supervisor else None,
        decided_at=decided.created_at.isoformat(), key_id=key.id, key_name=key.name,
        log_index=log_index_of(db, decided.event_id),
        revoked_by=revoked.id if revoked else None,
    ), db.get(Submission, decided.submission_id)


def _rehearsal(db: DbSession, submission: Submission | None) -> dict[str, Any] | None:
    if submission is None or submission.rehearsal_digest is None:
        return None
    row = get_record(db, submission.rehearsal_digest)
    return {**record_summary(db, row), "created_at": row.created_at.isoformat(),
            "record": row.record}


def version_document(db: DbSession, mission_id: str, number: int, *, reports: ReportService
                     ) -> tuple[MissionVersion, list[Section]]:
    version = get_version(db, mission_id, number)
    orders = orders_from_data(version.orders)
    report = report_for(db, orders, version.digest, reports=reports).report
    decision, submission = _decision(db, version)
    pending = None
    if decision is None and submission is not None:
        pending = f"submission {submission.id} is {submission.state}"
    return version, approval_document(
        mission=mission_id, version=number, digest=version.digest, orders=orders,
        findings=report["findings"], paths=report.get("paths"),
        rehearsal=_rehearsal(db, submission), decision=decision, pending=pending)
