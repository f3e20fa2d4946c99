"""A mission's standing: its latest approved version (an approval not revoked) and its latest
decision, kept apart so that a rejected v2 does not hide that v1 stands approved."""

from __future__ import annotations

from dataclasses import dataclass

from sqlalchemy import select
from sqlalchemy.orm import Session

from .tables import Approval, MissionVersion


@dataclass(frozen=True)
class Decision:
    version: int
    decision: str
    record: int


@dataclass(frozen=True)
class Standing:
    approved: Decision | None
    latest: Decision | None


def mission_standing(db: Session, mission_id: str) -> Standing:
    rows = db.execute(
        select(Approval.id, Approval.decision, Approval.revokes, MissionVersion.number)
        .join(MissionVersion, MissionVersion.id == Approval.version_id)
        .where(Approval.mission_id == mission_id).order_by(Approval.id)).all()
    revoked = {row.revokes for row in rows if row.decision == "revoked"}
    decisions = [Decision(row.number, row.decision, row.id) for row in rows]
    approved = [d for d in decisions if d.decision == "approved" and d.record not in revoked]
    return Standing(approved=max(approved, key=lambda d: d.version, default=None),
                    latest=decisions[-1] if decisions else None)
