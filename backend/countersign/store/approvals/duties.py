"""Who may decide on a version (roles, separation of duties) and its predecessor."""

from __future__ import annotations

from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ...approvals.signer import LogSigner
from ...errors import DomainError
from ..decide_guard import (
    editors_up_to,
)
from ..logged_roles import decision_refusal_from_log
from ..tables import (
    Approval,
    MissionVersion,
    Submission,
    User,
)
from .common import Refused, Stale


def _editors(db: DbSession, version: MissionVersion) -> set[int]:
    """Everyone who authored or edited any revision leading to this version (decide_guard)."""
    return editors_up_to(db, version)


def _check_duties(db: DbSession, supervisor: User, version: MissionVersion,
                  submission: Submission, *, signer: LogSigner | None) -> None:
    if supervisor.role != "supervisor":
        raise Refused(f"the {supervisor.role} role may not sign decisions")
    # The row's role is not evidence (a database writer can set it): the log's is.
    mismatch = decision_refusal_from_log(db, supervisor, signer=signer)
    if mismatch is not None:
        raise Refused(mismatch)
    if supervisor.id in _editors(db, version) | {submission.submitted_by}:
        raise Refused("separation of duties: you authored, edited or submitted this version, "
                      "so another supervisor must decide on it")


# A version has at most one submission in these states (uq_submissions_active_version).
ACTIVE_STATES = ("submitted", "approved")


def submit_refusal(*, user: User, number: int, report: dict[str, Any],
                   active: Submission | None, detailed: bool = False) -> Refused | Stale | None:
    """Why this user may not submit version `number` (None when they may), given its report
    and its active submission: what the review page shows beside a disabled button, and what
    submitting raises. `detailed` names the finding codes and the submission."""
    if user.role != "operator":
        return Refused("only operators submit versions")
    errors = [f for f in report["findings"] if f["severity"] == "error"]
    if errors:
        codes = ", ".join(sorted({f["code"] for f in errors}))
        named = f" ({codes})" if detailed else ""
        return Stale(f"version {number} has {len(errors)} error finding(s){named}; fix them "
                     "in the draft and create a new version")
    if active is not None and active.state in ACTIVE_STATES:
        named = f" (submission {active.id})" if detailed else ""
        return Stale(f"version {number} is {active.state} already{named}")
    return None


def decision_refusal(db: DbSession, *, user: User, version: MissionVersion,
                     submission: Submission | None, signer: LogSigner | None) -> str | None:
    """Why this user may not sign a decision on this version (None when they may): what
    the review page shows beside a disabled button; signing checks it again."""
    if user.role != "supervisor":
        return f"the {user.role} role may not sign decisions"
    try:
        if submission is None:
            raise Stale("the version is not submitted")
        _check_duties(db, user, version, submission, signer=signer)
        if submission.state != "submitted":
            raise Stale(f"submission {submission.id} is {submission.state}; there is nothing "
                        "to decide")
    except DomainError as exc:  # Refused or Stale above, or what reading the log raises
        return str(exc)
    return None


def previous_approval(db: DbSession, version: MissionVersion) -> Approval | None:
    """The newest approval of an earlier version of the same mission (revoked or not)."""
    return db.scalar(
        select(Approval).join(MissionVersion, MissionVersion.id == Approval.version_id)
        .where(Approval.mission_id == version.mission_id, Approval.decision == "approved",
               MissionVersion.number < version.number)
        .order_by(MissionVersion.number.desc(), Approval.id.desc()).limit(1))
