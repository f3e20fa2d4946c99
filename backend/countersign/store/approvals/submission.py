"""Submitting a version for review, and withdrawing it; the rules of submitting."""

from __future__ import annotations

from typing import Any

from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session as DbSession

from ...approvals.signer import LogSigner
from ...orders.reader import orders_from_data
from ..decide_guard import lock_version
from ..events import record
from ..missions import NotFound, get_mission, get_version, report_for
from ..rehearsals import attach as attach_rehearsal
from ..report_service import ReportService
from ..tables import (
    MissionVersion,
    Submission,
    User,
    utcnow,
)
from .common import Refused, Stale
from .duties import ACTIVE_STATES, submit_refusal


def _report(db: DbSession, version: MissionVersion, reports: ReportService) -> dict[str, Any]:
    return report_for(db, orders_from_data(version.orders), version.digest,
                      reports=reports).report


def submit(db: DbSession, *, mission_id: str, number: int, operator: User,
           reports: ReportService, rehearsal: str | None = None,
           signer: LogSigner | None) -> Submission:
    mission = get_mission(db, mission_id)
    version = get_version(db, mission_id, number)
    lock_version(db, version.id)  # parallel submits of one version queue here
    report = _report(db, version, reports)
    active = db.scalar(select(Submission).where(
        Submission.version_id == version.id, Submission.state.in_(ACTIVE_STATES)))
    refused = submit_refusal(user=operator, number=number, report=report, active=active,
                             detailed=True)
    if refused is not None:
        raise refused
    submission = Submission(version_id=version.id, submitted_by=operator.id)
    db.add(submission)
    try:
        db.flush()
    except IntegrityError:  # uq_submissions_active_version: a parallel submit won
        raise Stale(f"version {number} was submitted by another request just now") from None
    mission.status = "submitted"
    record(db, signer=signer, kind="submission.created", actor=operator, mission_id=mission_id,
           after=version.digest, detail={"submission": submission.id, "version": number})
    if rehearsal is not None:
        attach_rehearsal(db, submission=submission, digest=rehearsal, actor=operator,
                         signer=signer)
    return submission


def get_submission(db: DbSession, submission_id: int) -> Submission:
    submission = db.get(Submission, submission_id)
    if submission is None:
        raise NotFound(f"no submission {submission_id}")
    return submission


def withdraw(db: DbSession, *, submission_id: int, operator: User,
             signer: LogSigner | None) -> Submission:
    submission = get_submission(db, submission_id)
    if submission.submitted_by != operator.id:
        raise Refused("only the operator who submitted it can withdraw a submission")
    if submission.state != "submitted":
        raise Stale(f"submission {submission_id} is {submission.state}, not submitted")
    version = db.get_one(MissionVersion, submission.version_id)
    submission.state, submission.decided_at = "withdrawn", utcnow()
    get_mission(db, version.mission_id).status = "withdrawn"
    record(db, kind="submission.withdrawn", actor=operator, mission_id=version.mission_id,
           after=version.digest, detail={"submission": submission_id, "version": version.number},
           signer=signer)
    return submission
