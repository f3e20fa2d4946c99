"""The audit bundle: everything an auditor needs to verify offline."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ...approvals.bundle_model import (
    BUNDLE_FORMAT,
    Bundle,
    BundleApprovalOut,
    BundleInclusionOut,
    BundleKeyOut,
    CheckpointOut,
    LogKeyOut,
)
from ...approvals.merkle import Tree
from ...approvals.signer import LogSigner
from ..db import writes
from ..log_gaps import LogEntriesMissing, approvals_without_entry, describe, missing_entries
from ..tables import (
    Approval,
    Campaign,
    CampaignAttachment,
    Checkpoint,
    LogEntry,
    MissionVersion,
    RehearsalRecord,
    SigningKey,
    Submission,
    User,
)
from .common import _now_text
from .listing import Filters, approvals_query
from .log import _checkpoint_now, _receipts, checkpoint_json, log_tree


def build_bundle(db: DbSession, *, signer: LogSigner,
                 mission: str | None = None) -> dict[str, Any]:
    """Everything an auditor needs to verify offline: the whole log, its checkpoints, the
    log key, the supervisors' keys, the envelopes with inclusion proofs and their orders."""
    if not writes(db):
        # One transaction sees the log, signs its checkpoint and reads what it covers.
        from ..db import database_of

        with database_of(db).session() as writer:
            return build_bundle(writer, signer=signer, mission=mission)
    gaps, orphans = missing_entries(db), approvals_without_entry(db)
    damaged = bool(gaps or orphans)
    if damaged:  # a log with holes: no new checkpoint, no proofs (store/log_gaps.py)
        latest = db.scalar(select(Checkpoint).order_by(Checkpoint.tree_size.desc()).limit(1))
        refusal: str | None = describe(gaps, orphans)
    else:
        latest, refusal = _checkpoint_now(db, signer)
    tree = log_tree(db, pending=True)
    rows = list(db.scalars(approvals_query(Filters(mission=mission)).order_by(None)
                           .order_by(Approval.id)))
    related = _related(db, rows)
    covered = latest.tree_size if latest is not None else 0
    approvals = [_approval_json(a, related.indexes.get(a.event_id), covered,
                                None if damaged else tree) for a in rows]
    bundle = Bundle(
        format=BUNDLE_FORMAT, created_at=_now_text(),
        # The mission the approvals were exported for (None: all); decisions of other
        # missions need no envelope in this bundle (approvals/log_rules.py).
        scope=mission,
        log_key=LogKeyOut(key_id=signer.key_id, public_key=signer.public_text,
                          origin=signer.origin, verifier_key=signer.verifier_key),
        entries=list(db.scalars(select(LogEntry.entry).order_by(LogEntry.index))),
        # The signer's receipt per entry (None where an entry has none: not appended by it).
        receipts=_receipts(db, tree.size), signer_refused=refusal,
        checkpoints=[CheckpointOut(**checkpoint_json(c)) for c in db.scalars(
            select(Checkpoint).order_by(Checkpoint.tree_size))],
        keys=_keys(db), orders=related.orders, approvals=approvals,
        # The records the approvals cite, by digest (replays: the record's replay URL).
        rehearsals={r.digest: r.record for r in db.scalars(select(RehearsalRecord).where(
            RehearsalRecord.digest.in_(sorted(related.rehearsals))))}
        if related.rehearsals else {},
        campaigns={c.digest: c.record for c in db.scalars(select(Campaign).where(
            Campaign.digest.in_(sorted(related.campaigns))))} if related.campaigns else {},
    ).to_json()
    if damaged:
        raise LogEntriesMissing(gaps, orphans, bundle)
    return bundle


@dataclass
class _Related:
    """What the approvals refer to, by the keys the bundle uses."""

    indexes: dict[int, int] = field(default_factory=dict)  # log index by event id
    orders: dict[str, Any] = field(default_factory=dict)  # orders by digest
    rehearsals: set[str] = field(default_factory=set)  # cited rehearsal records' digests
    campaigns: set[str] = field(default_factory=set)  # cited campaign records' digests


def _related(db: DbSession, rows: list[Approval]) -> _Related:
    """A few queries per 500 approvals, not several per approval."""
    related = _Related()
    submissions: dict[int, Submission] = {}
    versions: dict[int, MissionVersion] = {}
    for start in range(0, len(rows), 500):
        chunk = rows[start:start + 500]
        for event_id, index in db.execute(select(LogEntry.event_id, LogEntry.index).where(
                LogEntry.event_id.in_([a.event_id for a in chunk]))):
            related.indexes[event_id] = index
        submission_ids = sorted({a.submission_id for a in chunk} - set(submissions))
        submissions.update((s.id, s) for s in db.scalars(
            select(Submission).where(Submission.id.in_(submission_ids))))
        related.campaigns.update(db.scalars(select(CampaignAttachment.digest).where(
            CampaignAttachment.submission_id.in_(submission_ids))))
        version_ids = sorted({a.version_id for a in chunk} - set(versions))
        versions.update((v.id, v) for v in db.scalars(
            select(MissionVersion).where(MissionVersion.id.in_(version_ids))))
    for approval in rows:
        if approval.orders_digest not in related.orders:
            related.orders[approval.orders_digest] = versions[approval.version_id].orders
        rehearsal = submissions[approval.submission_id].rehearsal_digest
        if rehearsal is not None:
            related.rehearsals.add(rehearsal)
    return related


def _approval_json(approval: Approval, logged: int | None, covered: int,
                   tree: Tree | None) -> BundleApprovalOut:
    """One approval with its envelope and its inclusion proof (none from a damaged log,
    `tree` None, or for an entry the checkpoint does not cover)."""
    hashes = [h.hex() for h in tree.inclusion_proof(logged, covered)] \
        if tree is not None and logged is not None and logged < covered else []
    return BundleApprovalOut(
        id=approval.id, mission=approval.mission_id, decision=approval.decision,
        log_index=logged, envelope=approval.envelope,
        inclusion=BundleInclusionOut(index=logged, size=covered, hashes=hashes))


def _keys(db: DbSession) -> list[BundleKeyOut]:
    signing_keys = list(db.scalars(select(SigningKey).order_by(SigningKey.created_at)))
    users: dict[int, str] = {user_id: name for user_id, name in db.execute(
        select(User.id, User.username).where(User.id.in_({k.user_id for k in signing_keys})))}
    return [BundleKeyOut(key_id=k.id, public_key=k.public_key,
                         user=None if k.user_id is None else users.get(k.user_id, f"#{k.user_id}"),
                         created_at=k.created_at.isoformat(),
                         revoked_at=k.revoked_at.isoformat() if k.revoked_at else None)
            for k in signing_keys]
