"""Missions as the API shows them: summaries, details, the list, reports and paths.

The store holds missions, versions and reports; this module composes them into what a route
answers (plain data: dicts of the response fields), with the report service passed in."""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, Literal

from sqlalchemy import func, or_, select
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import defer

from ..approvals.signer import LogSigner
from ..errors import Conflict, Invalid
from ..orders.canonical import digest_of_json, goal_texts, orders_to_json
from ..orders.model import Orders, declares_probabilities
from ..orders.reader import orders_from_data, read_json
from ..store import missions as store
from ..store.accounts import username_of
from ..store.db import Database, writes
from ..store.mission_status import mission_status, mission_statuses
from ..store.report_service import ReportService
from ..store.tables import Mission, MissionVersion, User, ValidationReport
from ..store.vehicles import registry_stamp, with_registry
from ..verify import fingerprint
from ..verify.graph import MissionGraph
from ..verify.parts import part_keys_of_json
from ..verify.path_search import PathQuery, UnknownNode, count_matching, iter_matching, path_query
from ..verify.paths import (
    MissionPath,
    PathCounts,
    count_paths,
    iter_path_lines,
    iter_paths,
)
from ..verify.probability import path_probability_bounds
from ..verify.refine import checked_form


def _orders(data: dict[str, Any]) -> Orders:
    return orders_from_data(data)


@dataclass(frozen=True)
class Validated:
    """Orders about to be written: their digest, and their report if it is new (stored by
    `keep` in the write transaction that follows)."""

    digest: str
    new_report: dict[str, Any] | None
    # The orders as JSON data, made once for the digest and stored as the draft.
    draft: dict[str, Any]

    def keep(self, db: DbSession) -> None:
        if self.new_report is not None:
            store.remember_report(db, self.new_report)


def registered(database: Database, orders: Orders) -> Orders:
    """with_registry in a read session of its own: read through the writer's session, it
    began the write transaction (SQLite's write lock) before the validation that follows."""
    with database.session(write=False) as reader:
        return with_registry(reader, orders)


def validate_first(db: DbSession, orders: Orders, *, database: Database,
                   reports: ReportService, mission_id: str | None = None,
                   expected_revision: int | None = None) -> Validated:
    """Validate orders about to be written before the write transaction begins. A writing
    request holds the write lock from its first query to its commit, so validating here (in
    a read transaction, without any lock) keeps that stretch short; the new report is then
    stored in the write transaction itself, so that neither this answer nor the next read
    validates again. An edit whose revision is already stale fails with 412 before paying
    for validation."""
    draft = orders_to_json(orders)
    # Each goal's JSON text, made once for the digest and the report parts' keys.
    texts = goal_texts(draft)
    value = digest_of_json(draft, texts)
    with database.session(write=False) as reader:
        if mission_id is not None and expected_revision is not None:
            # The revision alone: loading the row would decode its whole draft for nothing.
            current = reader.scalar(select(Mission.revision).where(Mission.id == mission_id))
            if current is not None and current != expected_revision:
                raise store.PreconditionFailed(
                    f"the draft changed since revision {expected_revision} (now "
                    f"{current}); reload it and apply your edit again", current)
        found = store.lookup_report(reader, orders, value, reports=reports,
                                    keys=part_keys_of_json(draft, texts))
    return Validated(value, None if found.cached else found.report, draft)


def create_mission(db: DbSession, orders: Orders, *, author: User, database: Database,
                   reports: ReportService, signer: LogSigner | None) -> Mission:
    """A new mission of these orders (the registry's profile and charts copied in), its
    report validated before the write and stored with it."""
    orders = registered(database, orders)
    validated = validate_first(db, orders, database=database, reports=reports)
    mission = store.create_mission(db, orders=orders, author=author,
                                   orders_digest=validated.digest, draft=validated.draft,
                                   signer=signer)
    validated.keep(db)
    return mission


def update_draft(db: DbSession, orders: Orders, *, mission_id: str,
                 layout: dict[str, Any] | None, expected_revision: int, author: User,
                 database: Database, reports: ReportService, signer: LogSigner | None) -> Mission:
    """The draft replaced by these orders (compare-and-set on the revision), validated first."""
    orders = registered(database, orders)
    validated = validate_first(db, orders, database=database, reports=reports,
                               mission_id=mission_id, expected_revision=expected_revision)
    mission = store.update_draft(
        db, mission_id=mission_id, orders=orders, layout=layout,
        expected_revision=expected_revision, author=author, orders_digest=validated.digest,
        draft=validated.draft, signer=signer)
    validated.keep(db)
    return mission


def summary_fields(mission: Mission, report: dict[str, Any] | None, latest: int | None,
                   updated_by: str, status: tuple[str, list[str]]) -> dict[str, Any]:
    findings = report["findings"] if report else None
    errors = sum(f["severity"] == "error" for f in findings) if findings is not None else None
    return counted_summary_fields(
        mission, report["ok"] if report else None, errors,
        (len(findings) - (errors or 0)) if findings is not None else None, latest, updated_by,
        status)


def counted_summary_fields(mission: Mission, ok: bool | None, errors: int | None,
                           warnings: int | None, latest: int | None,
                           updated_by: str, status: tuple[str, list[str]]) -> dict[str, Any]:
    """A mission's summary from counts already made (the report's summary columns)."""
    return {
        "id": mission.id, "title": mission.title, "vehicle": mission.vehicle,
        "status": status[0], "integrity": status[1], "draft_digest": mission.draft_digest,
        "revision": mission.revision, "latest_version": latest,
        "ok": ok, "errors": errors, "warnings": warnings,
        "updated_at": mission.updated_at, "updated_by": updated_by,
    }


def summary(db: DbSession, mission: Mission, *, reports: ReportService,
            names: dict[int, str], latest: int | Literal[False] | None = False,
            status: tuple[str, list[str]] | None = None) -> dict[str, Any]:
    """The summary fields of a mission."""
    if latest is False:
        latest = db.scalar(select(func.max(MissionVersion.number))
                           .where(MissionVersion.mission_id == mission.id))
    updated_by = username_of(db, mission.updated_by, names)
    shown = status or mission_status(db, mission)
    # The stored report's summary columns, as the list reads them: an answer after a save
    # does not decode the report it has just stored.
    counts = store.report_counts(db, mission.draft_digest)
    if counts is not None:
        return counted_summary_fields(mission, *counts, latest, updated_by, shown)
    # A writing request holds the write lock until it answers: it reports only what is cached
    # (ok/errors stay null otherwise) and leaves validation to the next read or /validate.
    if writes(db):
        report = store.cached_report(db, mission.draft_digest)
    else:
        report = store.report_for(db, lambda: _orders(mission.draft), mission.draft_digest,
                                  reports=reports).report
    return summary_fields(mission, report, latest, updated_by, shown)


def detail(db: DbSession, mission: Mission, *, reports: ReportService,
           import_findings: list[dict[str, Any]] | None = None) -> dict[str, Any]:
    """The detail fields of a mission: its summary, draft, layout and versions (each
    version's number, digest, author and time)."""
    names: dict[int, str] = {}
    # The list needs no version's orders: select the four columns it shows.
    rows = db.execute(
        select(MissionVersion.number, MissionVersion.digest, MissionVersion.author_id,
               MissionVersion.created_at)
        .where(MissionVersion.mission_id == mission.id).order_by(MissionVersion.number)
    ).all()
    versions = [{"number": number, "digest": value, "author": username_of(db, author, names),
                 "created_at": created_at}
                for number, value, author, created_at in rows]
    latest: int | None = rows[-1][0] if rows else None
    return {**summary(db, mission, reports=reports, names=names, latest=latest),
            "orders": mission.draft, "layout": mission.layout, "versions": versions,
            "import_findings": import_findings or []}


def encode_cursor(value: str | int) -> str:
    return base64.urlsafe_b64encode(str(value).encode()).decode()


def decode_cursor(cursor: str) -> str:
    try:
        return base64.b64decode(cursor.encode(), altchars=b"-_", validate=True).decode()
    except (ValueError, UnicodeDecodeError):
        raise Invalid("the cursor is not valid; start again without one") from None


@dataclass(frozen=True)
class MissionList:
    items: list[dict[str, Any]]
    next_cursor: str | None


def list_missions(db: DbSession, *, reports: ReportService, q: str | None,
                  status: str | None, vehicle: str | None, limit: int,
                  cursor: str | None) -> MissionList:
    # One query: each mission's row without its orders or layout, its draft report's summary
    # columns (never the report itself) and its latest version number.
    latest = (select(func.max(MissionVersion.number))
              .where(MissionVersion.mission_id == Mission.id).scalar_subquery())
    query = (
        select(Mission, ValidationReport.ok, ValidationReport.errors, ValidationReport.warnings,
               latest)
        .options(defer(Mission.draft), defer(Mission.layout))
        .outerjoin(ValidationReport,
                   (ValidationReport.digest == Mission.draft_digest)
                   & (ValidationReport.checker_version == fingerprint.checker_fingerprint()))
        .order_by(Mission.id).limit(limit + 1)
    )
    if q:
        pattern = "%" + q.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_") + "%"
        query = query.where(or_(Mission.id.ilike(pattern, escape="\\"),
                                Mission.title.ilike(pattern, escape="\\")))
    if status:
        query = query.where(Mission.status == status)
    if vehicle:
        query = query.where(Mission.vehicle == vehicle)
    if cursor:
        query = query.where(Mission.id > decode_cursor(cursor))
    rows = db.execute(query).all()
    names: dict[int, str] = {}
    items = []
    statuses = mission_statuses(db, [row[0] for row in rows[:limit]])
    for mission, ok, errors, warnings, number in rows[:limit]:
        shown = statuses[mission.id]
        if errors is None or warnings is None:  # no current report yet: as the detail does
            fields = summary(db, mission, reports=reports, names=names, latest=number,
                             status=shown)
        else:
            fields = counted_summary_fields(mission, ok, errors, warnings, number,
                                            username_of(db, mission.updated_by, names), shown)
        items.append(fields)
    following = encode_cursor(rows[limit - 1][0].id) if len(rows) > limit else None
    return MissionList(items, following)


def draft_report(db: DbSession, *, reports: ReportService, mission_id: str) -> dict[str, Any]:
    """The report of the mission's draft, as stored (computed and stored when missing)."""
    # The digest alone: the draft (a 1,000-goal mission's is 300 kB of JSON to decode) is read
    # only when its report must be made.
    value = store.draft_digest(db, mission_id)
    # The editor reads the report of the draft it has just saved: made here, it is answered
    # from memory rather than decoded from its stored copy (700 kB of JSON at 1,000 goals).
    made = reports.recent(value)
    if made is not None:
        return made
    return store.report_for(db, lambda: _orders(store.draft_of(db, mission_id, value)), value,
                            reports=reports).report


def validate_body(db: DbSession, *, reports: ReportService, data: bytes) -> dict[str, Any]:
    """The report of orders sent as a JSON body (the importer's JSON reader: duplicate keys,
    bad UTF-8 and bad JSON are read errors)."""
    # The same body sent again (an editor re-checking, a CI job) skips parsing and
    # canonicalising: the report service remembers the orders digest of recent bodies. The
    # registry's profiles and charts are copied into the orders, so they are part of the key.
    key = hashlib.sha256(registry_stamp(db) + b"\0" + data).digest()
    known = reports.body_digest(key)
    if known is not None:
        stored = store.cached_report(db, known)
        if stored is not None:
            return stored
    report = store.report_for(db, with_registry(db, read_json(data)), reports=reports).report
    reports.remember_body(key, report["digest"])
    return report


@dataclass(frozen=True)
class PathListing:
    """The paths of one mission's orders, from `offset` (of all paths, or of the matching
    ones when `searching`)."""

    graph: MissionGraph
    counts: PathCounts
    bounds: list[tuple[tuple[float, float], ...]] | None
    query: PathQuery
    searching: bool
    matching: int
    offset: int

    def lines(self) -> Iterator[str]:
        for line in iter_path_lines(self.graph, self.counts, self.offset,
                                    probabilities=self.bounds):
            yield line + "\n"

    def page(self, limit: int) -> list[MissionPath]:
        if self.searching:
            return list(iter_matching(self.graph, self.counts, self.query, self.offset, limit,
                                      probabilities=self.bounds))
        return list(iter_paths(self.graph, self.counts, self.offset, limit,
                               probabilities=self.bounds))

    def next_cursor(self, shown: int) -> str | None:
        following = self.offset + shown
        return encode_cursor(following) if following < self.matching else None


def path_listing(db: DbSession, *, mission_id: str, version: int | None, goal: str | None,
                 terminal: str | None, cursor: str | None) -> PathListing:
    """The paths in the order of Figure 6 from the cursor on. With `goal` or `terminal`, only
    the matching paths (`matching` counts them), each keeping its index in the full list; the
    cursor then counts matches."""
    if version is not None:
        orders = _orders(store.get_version(db, mission_id, version).orders)
    else:
        orders = _orders(store.get_mission(db, mission_id).draft)
    if orders.team is not None:
        # A team has one path list per member; its joint executions are counted in the report.
        raise Conflict("these orders are a team's: each member has its own paths, "
                       "and the report counts the joint executions")
    # Refined goals run as their refinements: the paths are those of the flat mission.
    orders, graph = checked_form(orders)
    counts = count_paths(graph)
    bounds = (path_probability_bounds(orders, graph)
              if declares_probabilities(orders) else None)
    if counts is None:
        raise Conflict("the paths cannot be counted until the structural errors "
                       "in the report are fixed")
    searching = bool(goal or terminal)
    try:
        query = path_query(graph, goal, terminal)
    except UnknownNode as e:
        raise Invalid(f"{e}: search by one of its goal or terminal ids") from None
    matching = count_matching(graph, query) if searching else counts.total
    assert matching is not None  # counted above
    offset = 0
    if cursor:
        try:
            offset = int(decode_cursor(cursor))
        except ValueError:
            raise Invalid("the cursor is not valid") from None
        if not 0 <= offset <= matching:  # e.g. "LTE=", which decodes to -1
            raise Invalid("the cursor is not valid")
    return PathListing(graph, counts, bounds, query, searching, matching, offset)
