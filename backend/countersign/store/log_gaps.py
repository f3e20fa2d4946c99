"""Log entries missing from the database: rows deleted by a writer that is not the app (the
append-only triggers bypassed). The log's indexes run 0..n-1 with no gap, and no signed
checkpoint covers more entries than the table holds; an audit bundle of a log with holes is
named as a conflict (409) instead of failing inside the Merkle proofs."""

from __future__ import annotations

from typing import Any

from sqlalchemy import func, select
from sqlalchemy.orm import Session as DbSession

from ..errors import Conflict
from .tables import Approval, Checkpoint, LogEntry

Gap = tuple[int, int]  # first and last missing index, inclusive


class LogEntriesMissing(Conflict):
    """The log table lacks entries; `bundle` is what the database still holds, for
    `countersign audit verify` to name every consequence."""

    def __init__(self, gaps: list[Gap], approvals: list[int], bundle: dict[str, Any]) -> None:
        super().__init__(describe(gaps, approvals))
        self.gaps = gaps
        self.approvals = approvals
        self.bundle = bundle

    def extra(self) -> dict[str, Any]:
        return {"missing_entries": [{"first": a, "last": b} for a, b in self.gaps],
                "approvals_without_entry": self.approvals, "bundle": self.bundle}


def missing_entries(db: DbSession) -> list[Gap]:
    """Every run of indexes absent below the log's size (its highest index or the largest
    signed checkpoint, whichever says more)."""
    size = max(db.scalar(select(func.max(LogEntry.index))) or -1,
               (db.scalar(select(func.max(Checkpoint.tree_size))) or 0) - 1) + 1
    if db.scalar(select(func.count()).select_from(LogEntry)) == size:
        return []  # the common case: one count, no scan
    gaps: list[Gap] = []
    expected = 0
    for index in db.scalars(select(LogEntry.index).order_by(LogEntry.index)):
        if index > expected:
            gaps.append((expected, index - 1))
        expected = index + 1
    if expected < size:
        gaps.append((expected, size - 1))
    return gaps


def approvals_without_entry(db: DbSession) -> list[int]:
    logged = select(LogEntry.event_id)
    return list(db.scalars(select(Approval.id).where(Approval.event_id.not_in(logged))
                           .order_by(Approval.id)))


def describe(gaps: list[Gap], approvals: list[int]) -> str:
    runs = ", ".join(f"log entry {a} is missing" if a == b else f"log entries {a}..{b} are "
                     "missing" for a, b in gaps)
    text = f"the log was altered outside the app: {runs}"
    if approvals:
        text += "; the log entry of " + ", ".join(f"approval {i}" for i in approvals) + \
            " is gone"
    return text + (" (the problem's `bundle` holds what remains, for `countersign audit "
                   "verify`)")
