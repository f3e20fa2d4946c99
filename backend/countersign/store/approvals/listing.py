"""Listing approvals: filters and summaries."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import Select, select
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import aliased

from ..integrity import approval_integrity
from ..tables import (
    Approval,
    MissionVersion,
    User,
)
from .common import _username
from .log import log_index_of


@dataclass(frozen=True)
class Filters:
    mission: str | None = None
    operator: str | None = None
    supervisor: str | None = None
    vehicle: str | None = None
    decision: str | None = None
    since: datetime | None = None
    until: datetime | None = None


def approvals_query(filters: Filters) -> Select[Approval]:
    query = select(Approval).order_by(Approval.id.desc())
    if filters.mission:
        query = query.where(Approval.mission_id == filters.mission)
    if filters.vehicle:
        query = query.where(Approval.vehicle == filters.vehicle)
    if filters.decision:
        query = query.where(Approval.decision == filters.decision)
    if filters.since:
        query = query.where(Approval.created_at >= filters.since)
    if filters.until:
        query = query.where(Approval.created_at < filters.until)
    if filters.operator:
        author = aliased(User)
        query = query.join(author, author.id == Approval.author_id).where(
            author.username == filters.operator)
    if filters.supervisor:
        signer = aliased(User)
        query = query.join(signer, signer.id == Approval.supervisor_id).where(
            signer.username == filters.supervisor)
    return query


def approval_summary(db: DbSession, approval: Approval) -> dict[str, Any]:
    version = db.get_one(MissionVersion, approval.version_id)
    return {"id": approval.id, "mission": approval.mission_id, "version": version.number,
            "digest": approval.orders_digest, "vehicle": approval.vehicle,
            "decision": approval.decision, "reason": approval.reason,
            "revokes": approval.revokes, "operator": _username(db, approval.author_id),
            "supervisor": _username(db, approval.supervisor_id), "key_id": approval.key_id,
            "submission": approval.submission_id, "created_at": approval.created_at,
            "log_index": log_index_of(db, approval.event_id),
            # issue 14 item 5 (branch decisions): the row checked against its log entry.
            "integrity": approval_integrity(db, approval)}
