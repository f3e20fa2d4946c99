"""Listing approvals: filters and summaries."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import Select, select
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import aliased

from ..integrity import approval_problems, logged_events
from ..tables import (
    Approval,
    MissionVersion,
    User,
)


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
    return approval_summaries(db, [approval])[0]


def approval_summaries(db: DbSession, approvals: list[Approval]) -> list[dict[str, Any]]:
    """Each approval as the list shows it, with its row checked against its log entry. The
    versions, people and log entries of all of them are read in three queries, not per row."""
    numbers = dict(db.execute(select(MissionVersion.id, MissionVersion.number).where(
        MissionVersion.id.in_({a.version_id for a in approvals}))).all())
    people = {a.author_id for a in approvals} | {a.supervisor_id for a in approvals}
    names = dict(db.execute(select(User.id, User.username).where(
        User.id.in_(people - {None}))).all())
    logged = logged_events(db, [a.event_id for a in approvals])

    def name(user_id: int | None) -> str | None:
        return None if user_id is None else names.get(user_id, f"#{user_id}")

    out = []
    for approval in approvals:
        index, event = logged.get(approval.event_id, (None, None))
        out.append({
            "id": approval.id, "mission": approval.mission_id,
            "version": numbers[approval.version_id], "digest": approval.orders_digest,
            "vehicle": approval.vehicle, "decision": approval.decision,
            "reason": approval.reason, "revokes": approval.revokes,
            "operator": name(approval.author_id), "supervisor": name(approval.supervisor_id),
            "key_id": approval.key_id, "submission": approval.submission_id,
            "created_at": approval.created_at, "log_index": index,
            # The row checked against its log entry: the log, not the table, is the record.
            "integrity": approval_problems(approval, event)})
    return out
