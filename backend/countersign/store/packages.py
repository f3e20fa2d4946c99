"""Collects an approved package's parts from the database and the log (approved_package/)."""

from __future__ import annotations

from datetime import UTC, datetime

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.signer import LogSigner
from ..approved_package.build import PackageParts
from ..errors import Conflict
from ..orders.reader import orders_from_data
from . import missions as service
from .approvals import checkpoint_json, inclusion_proof, log_index_of, vouched_checkpoint
from .tables import Approval, LogEntry, LogReceipt


class NotApproved(Conflict):
    """The version has no standing approval (none, or revoked)."""


def standing_approval(db: DbSession, version_id: int) -> Approval | None:
    rows = list(db.scalars(select(Approval).where(Approval.version_id == version_id)
                           .order_by(Approval.id)))
    revoked = {r.revokes for r in rows if r.decision == "revoked"}
    approved = [r for r in rows if r.decision == "approved" and r.id not in revoked]
    return approved[-1] if approved else None


def package_parts(db: DbSession, *, mission_id: str, number: int, signer: LogSigner,
                  standing_only: bool = True, now: datetime | None = None) -> PackageParts:
    """Parts of the package of a version's approval; refuses a version without a standing
    approval (tests pass standing_only=False to package a revoked one on purpose). The
    checkpoint carries the log's timestamp of `now` (default: the present) when the signer
    vouches that it is its latest head."""
    version = service.get_version(db, mission_id, number)
    rows = list(db.scalars(select(Approval).where(Approval.version_id == version.id)
                           .order_by(Approval.id)))
    revoked = {r.revokes for r in rows if r.decision == "revoked"}
    approved = [r for r in rows if r.decision == "approved"
                and (r.id not in revoked or not standing_only)]
    if not approved:
        raise NotApproved(f"version {number} of {mission_id} has no standing approval")
    approval = approved[-1]
    index = log_index_of(db, approval.event_id)
    if index is None:
        raise NotApproved("the approval has no log entry")
    checkpoint = checkpoint_json(vouched_checkpoint(db, signer=signer))
    size = int(checkpoint["size"])
    if index >= size:
        raise NotApproved("the newest checkpoint does not cover the approval yet; retry")
    entries = list(db.scalars(select(LogEntry.entry).where(LogEntry.index < size)
                              .order_by(LogEntry.index)))
    receipts = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt).where(
        LogReceipt.index.in_([index, size - 1]))).all())
    proof = inclusion_proof(db, index=index, size=size)
    return PackageParts(
        orders=orders_from_data(version.orders), version=version.number,
        envelope=approval.envelope, approval_index=index, entries=entries,
        receipt=receipts.get(index) or "", head_receipt=receipts.get(size - 1) or "",
        inclusion={"index": index, "size": size, "hashes": proof["hashes"]},
        checkpoint=str(checkpoint["signed_note"]) + (signer.timestamp_head(
            str(checkpoint["note"]), int((now or datetime.now(UTC)).timestamp())) or ""))
