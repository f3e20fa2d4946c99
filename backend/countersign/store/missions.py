"""Missions, their draft heads, immutable versions and cached validation reports."""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from cachetools import LRUCache
from sqlalchemy import delete, func, select, update
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import defer
from sqlalchemy.orm.attributes import set_committed_value

from ..approvals.signer import LogSigner
from ..errors import Conflict, Invalid, NotFound, PreconditionFailed
from ..orders.canonical import digest, orders_to_json
from ..orders.model import Orders
from ..verify import fingerprint
from . import draft_bursts
from .db import writable
from .events import record
from .report_service import ReportService
from .tables import Mission, MissionVersion, User, ValidationReport, utcnow

if TYPE_CHECKING:
    from ..verify.parts import PartKeys

MAX_LAYOUT_NODES = 50_000
# The draft this process last wrote for each of the missions edited most recently, with its
# digest. The next save of the mission compares its draft with that one (the editing burst's
# list of changes) instead of decoding the stored draft, 300 kB of JSON at 1,000 goals; a row
# whose digest differs (a save by another process, or one rolled back) is read as before.
# Drafts are shared, never mutated.
DRAFTS_KEPT = 16
_last_drafts: LRUCache[str, tuple[str, dict[str, Any]]] = LRUCache(DRAFTS_KEPT)
_last_drafts_lock = threading.Lock()


# The domain's errors (countersign.errors), under the names the store has always used.
__all__ = ["BadDraft", "Conflict", "NotFound", "PreconditionFailed"]


class BadDraft(Invalid):
    """A draft that cannot be saved as sent (an id that changes, a layout too large)."""


def _check_layout(layout: dict[str, Any]) -> dict[str, Any]:
    if len(layout) > MAX_LAYOUT_NODES:
        raise BadDraft(f"the layout may hold at most {MAX_LAYOUT_NODES} entries")
    return layout


def get_mission(db: DbSession, mission_id: str) -> Mission:
    mission = db.get(Mission, mission_id)
    if mission is None:
        raise NotFound(f"no mission {mission_id!r}")
    return mission


def _wrote(mission_id: str, orders_digest: str, draft: dict[str, Any]) -> None:
    with _last_drafts_lock:
        _last_drafts[mission_id] = (orders_digest, draft)


def _previous_draft(mission: Mission) -> dict[str, Any]:
    """The mission's stored draft, from what this process wrote last when it is that one."""
    with _last_drafts_lock:
        kept = _last_drafts.get(mission.id)
    if kept is not None and kept[0] == mission.draft_digest:
        return kept[1]
    return mission.draft


def draft_digest(db: DbSession, mission_id: str) -> str:
    """The digest of the mission's draft, without loading the draft."""
    value = db.scalar(select(Mission.draft_digest).where(Mission.id == mission_id))
    if value is None:
        raise NotFound(f"no mission {mission_id!r}")
    return value


def draft_of(db: DbSession, mission_id: str, orders_digest: str) -> dict[str, Any]:
    """The mission's draft of this digest (read after draft_digest: on PostgreSQL each
    statement of a read sees the latest commit, and a report made from a newer draft must
    never be filed under the older digest)."""
    draft: dict[str, Any] | None = db.scalar(select(Mission.draft).where(
        Mission.id == mission_id, Mission.draft_digest == orders_digest))
    if draft is None:
        raise Conflict(f"the draft of mission {mission_id!r} changed while its report was "
                       "read; ask again")
    return draft


def create_mission(
    db: DbSession, *, orders: Orders, author: User, layout: dict[str, Any] | None = None,
    orders_digest: str | None = None, draft: dict[str, Any] | None = None,
    signer: LogSigner | None,
) -> Mission:
    """A new mission; `draft` is orders_to_json(orders) when the caller made it already."""
    if db.get(Mission, orders.id) is not None:
        raise Conflict(f"a mission with id {orders.id!r} exists already; choose another id")
    value = orders_digest or digest(orders)
    mission = Mission(
        id=orders.id, title=orders.title, vehicle=orders.vehicle,
        draft=orders_to_json(orders) if draft is None else draft,
        draft_digest=value, layout=_check_layout(layout or {}), revision=1,
        created_by=author.id, updated_by=author.id,
    )
    db.add(mission)
    try:
        db.flush()
    except IntegrityError:
        raise Conflict(f"a mission with id {orders.id!r} exists already") from None
    record(db, kind="mission.created", actor=author, mission_id=orders.id, after=value,
           log_at_commit=True, signer=signer)
    _wrote(mission.id, value, mission.draft)
    return mission


def update_draft(
    db: DbSession, *, mission_id: str, orders: Orders, layout: dict[str, Any] | None,
    expected_revision: int, author: User, orders_digest: str | None = None,
    draft: dict[str, Any] | None = None, signer: LogSigner | None,
) -> Mission:
    """Compare-and-set on the revision: a concurrent edit fails with 412, nothing is lost.
    The save joins its author's editing burst, logged once when it ends (draft_bursts.py).
    `draft` is orders_to_json(orders) when the caller made it already."""
    # The stored draft is decoded only if this process did not write it (_previous_draft).
    mission = db.get(Mission, mission_id, options=[defer(Mission.draft)])
    if mission is None:
        raise NotFound(f"no mission {mission_id!r}")
    if orders.id != mission_id:
        raise BadDraft(
            f"the orders' id {orders.id!r} differs from the mission {mission_id!r}; "
            "ids cannot change"
        )
    before = mission.draft_digest
    value = orders_digest or digest(orders)
    draft = orders_to_json(orders) if draft is None else draft
    now = utcnow()
    if mission.burst is not None and not draft_bursts.joins(mission, author, now):
        # Someone else's burst, or one that went quiet.
        draft_bursts.flush(db, mission, signer=signer)
    burst = draft_bursts.extended(mission, author, previous=_previous_draft(mission),
                                  draft=draft, before=before, revision=expected_revision + 1,
                                  now=now)
    changes: dict[str, Any] = {
        "draft": draft, "draft_digest": value, "title": orders.title,
        "vehicle": orders.vehicle, "revision": Mission.revision + 1,
        "updated_by": author.id, "updated_at": now, "burst": burst, "burst_at": now,
    }
    if layout is not None:
        changes["layout"] = _check_layout(layout)
    result = db.execute(
        update(Mission)
        .where(Mission.id == mission_id, Mission.revision == expected_revision)
        .values(**changes)
        .execution_options(synchronize_session=False)
    )
    if result.rowcount != 1:  # type: ignore[attr-defined]
        db.refresh(mission)
        raise PreconditionFailed(
            f"the draft changed since revision {expected_revision} (now {mission.revision}); "
            "reload it and apply your edit again",
            mission.revision,
        )
    # The row now holds exactly what was written (the revision was `expected_revision`):
    # set it on the object rather than reading it back, which decoded the whole draft again.
    changes["revision"] = expected_revision + 1
    for name, written in changes.items():
        set_committed_value(mission, name, written)
    _wrote(mission_id, value, draft)
    return mission


def save_layout(db: DbSession, *, mission_id: str, layout: dict[str, Any]) -> Mission:
    """The editor's node positions, stored beside the draft: not orders, so no revision, no
    "Updated by" and no event (two operators moving nodes never conflict on the draft)."""
    mission = get_mission(db, mission_id)
    db.execute(
        update(Mission).where(Mission.id == mission_id).values(layout=_check_layout(layout))
        .execution_options(synchronize_session=False)
    )
    db.refresh(mission)
    return mission


def delete_mission(db: DbSession, *, mission_id: str, actor: User,
                   signer: LogSigner | None) -> None:
    mission = get_mission(db, mission_id)
    versions = db.scalar(
        select(func.count()).select_from(MissionVersion)
        .where(MissionVersion.mission_id == mission_id)
    )
    if versions:
        raise Conflict(
            f"mission {mission_id!r} has {versions} version(s); only drafts can be deleted"
        )
    draft_bursts.flush(db, mission, signer=signer)
    record(db, signer=signer, kind="mission.deleted", actor=actor, mission_id=mission_id,
           before=mission.draft_digest, log_at_commit=True)
    db.delete(mission)


def create_version(db: DbSession, *, mission_id: str, author: User,
                   signer: LogSigner | None) -> MissionVersion:
    mission = get_mission(db, mission_id)
    # The edits that led to this version are in the log before it (separation of duties).
    draft_bursts.flush(db, mission, signer=signer)
    latest = db.scalar(
        select(func.max(MissionVersion.number)).where(MissionVersion.mission_id == mission_id)
    ) or 0
    version = MissionVersion(mission_id=mission_id, number=latest + 1, orders=mission.draft,
                             digest=mission.draft_digest, author_id=author.id)
    db.add(version)
    try:
        db.flush()
    except IntegrityError:
        raise Conflict("another version was created at the same moment; try again") from None
    record(db, signer=signer, kind="version.created", actor=author, mission_id=mission_id,
           after=version.digest, detail={"number": version.number}, log_at_commit=True)
    return version


def get_version(db: DbSession, mission_id: str, number: int) -> MissionVersion:
    version = db.scalar(select(MissionVersion).where(
        MissionVersion.mission_id == mission_id, MissionVersion.number == number))
    if version is None:
        raise NotFound(f"mission {mission_id!r} has no version {number}")
    return version


@dataclass(frozen=True)
class CachedReport:
    report: dict[str, Any]
    cached: bool


def cached_report(db: DbSession, orders_digest: str) -> dict[str, Any] | None:
    """The stored report of this digest made by the current checks, or None: a report of
    other checks (before an upgrade) is never answered."""
    row = db.get(ValidationReport, (orders_digest, fingerprint.checker_fingerprint()))
    return row.report if row is not None else None


def report_counts(db: DbSession, orders_digest: str) -> tuple[bool, int, int] | None:
    """ok, errors and warnings of the stored report of this digest by the current checks,
    from its summary columns (the report itself, hundreds of kilobytes of JSON for a
    1,000-goal mission, is not decoded); None without such a report or columns."""
    row = db.execute(select(ValidationReport.ok, ValidationReport.errors,
                            ValidationReport.warnings)
                     .where(ValidationReport.digest == orders_digest,
                            ValidationReport.checker_version
                            == fingerprint.checker_fingerprint())).first()
    if row is None or row.ok is None or row.errors is None or row.warnings is None:
        return None
    return bool(row.ok), row.errors, row.warnings


def report_for(
    db: DbSession, orders: Orders | Callable[[], Orders], orders_digest: str | None = None,
    *, reports: ReportService,
) -> CachedReport:
    """The validation report of these orders, computed once per digest and checker
    fingerprint (verify.fingerprint): a report stored by other checks is computed again.

    `orders` may be a loader, called only on a cache miss: with the digest known, a cached
    report costs one lookup and no parsing. A read-only session stores a new report through a
    short transaction of its own, so that readers never hold (or wait for) a write lock while
    validating. A report not stored is computed by `reports` (once per digest in this process,
    with the web app's pool of validation processes while it runs)."""
    found = lookup_report(db, orders, orders_digest, reports=reports)
    if not found.cached:
        remember_report(db, found.report)
    return found


def lookup_report(
    db: DbSession, orders: Orders | Callable[[], Orders], orders_digest: str | None = None,
    *, reports: ReportService, keys: PartKeys | None = None,
) -> CachedReport:
    """The stored report of these orders, or a new one computed but not stored (its `cached`
    is False: store it with remember_report, e.g. in the write transaction that follows).
    `keys`: the orders' part keys, when the caller made them (verify.parts)."""
    if orders_digest is None:
        orders = orders() if callable(orders) else orders
        orders_digest = digest(orders)
    row = db.get(ValidationReport, (orders_digest, fingerprint.checker_fingerprint()))
    if row is not None:
        return CachedReport(row.report, True)
    return CachedReport(reports.report(orders_digest, orders() if callable(orders) else orders,
                                       keys), False)


def report_summary(report: dict[str, Any]) -> dict[str, Any]:
    """The columns stored beside a report for the mission list: ok, errors, warnings."""
    findings = report["findings"]
    errors = sum(finding["severity"] == "error" for finding in findings)
    return {"ok": bool(report["ok"]), "errors": errors, "warnings": len(findings) - errors}


def remember_report(db: DbSession, report: dict[str, Any]) -> None:
    """Store a report computed by lookup_report (in a savepoint of a writing session, else in
    a short write transaction of its own), under the checker fingerprint it carries; the
    reports of the same orders by other checks go, as nothing reads them again. A concurrent
    request may have stored it first."""
    checker = report["checker"]
    try:
        with writable(db) as writer:
            writer.execute(delete(ValidationReport).where(
                ValidationReport.digest == report["digest"],
                ValidationReport.checker_version != checker,
            ).execution_options(synchronize_session=False))
            writer.add(ValidationReport(digest=report["digest"], checker_version=checker,
                                        report=report, **report_summary(report)))
    except IntegrityError:
        pass  # a concurrent request stored the same report first
