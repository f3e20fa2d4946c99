"""Database tables (SQLAlchemy 2.0). One metadata object, imported by Alembic's env.py.

Mission versions and events are immutable once written: the code only ever inserts them.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from sqlalchemy import (
    JSON,
    BigInteger,
    Boolean,
    DateTime,
    Float,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    MetaData,
    String,
    Text,
    UniqueConstraint,
    text,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column
from sqlalchemy.types import TypeDecorator

NAMING = {
    "ix": "ix_%(column_0_label)s",
    "uq": "uq_%(table_name)s_%(column_0_name)s",
    "ck": "ck_%(table_name)s_%(constraint_name)s",
    "fk": "fk_%(table_name)s_%(column_0_name)s_%(referred_table_name)s",
    "pk": "pk_%(table_name)s",
}

ROLES = ("operator", "supervisor", "auditor", "admin")


def utcnow() -> datetime:
    return datetime.now(UTC)


class UtcDateTime(TypeDecorator[datetime]):
    """Timestamps are stored and returned as UTC; SQLite would otherwise drop the zone."""

    impl = DateTime(timezone=True)
    cache_ok = True

    def process_bind_param(self, value: datetime | None, dialect: Any) -> datetime | None:
        if value is not None and value.tzinfo is None:
            raise ValueError("timestamps must carry a time zone")
        return value.astimezone(UTC) if value is not None else None

    def process_result_value(self, value: datetime | None, dialect: Any) -> datetime | None:
        if value is None:
            return None
        return value.replace(tzinfo=UTC) if value.tzinfo is None else value.astimezone(UTC)


class Base(DeclarativeBase):
    metadata = MetaData(naming_convention=NAMING)
    # SQLAlchemy reads this class attribute itself; it is never mutated.
    type_annotation_map = {dict[str, Any]: JSON, datetime: UtcDateTime()}  # noqa: RUF012


class User(Base):
    __tablename__ = "users"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    username: Mapped[str] = mapped_column(String(64), unique=True)
    display_name: Mapped[str] = mapped_column(String(200), default="")
    role: Mapped[str] = mapped_column(String(16))
    password_hash: Mapped[str] = mapped_column(String(255))
    disabled: Mapped[bool] = mapped_column(Boolean, default=False)
    created_at: Mapped[datetime] = mapped_column(default=utcnow)


class Session(Base):
    __tablename__ = "sessions"
    # sha256 of the cookie value: a stolen database does not yield live sessions.
    token_hash: Mapped[str] = mapped_column(String(64), primary_key=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    csrf_token: Mapped[str] = mapped_column(String(64))
    created_at: Mapped[datetime] = mapped_column(default=utcnow)
    expires_at: Mapped[datetime]  # the absolute timeout
    # The idle timeout counts from here (written at most once a minute; None: since created).
    last_seen_at: Mapped[datetime | None] = mapped_column(default=None)


class ApiToken(Base):
    __tablename__ = "api_tokens"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    name: Mapped[str] = mapped_column(String(100))
    token_hash: Mapped[str] = mapped_column(String(64), unique=True)
    created_at: Mapped[datetime] = mapped_column(default=utcnow)
    last_used_at: Mapped[datetime | None] = mapped_column(default=None)
    revoked: Mapped[bool] = mapped_column(Boolean, default=False)
    expires_at: Mapped[datetime | None] = mapped_column(default=None)
    # Space-separated: read (GET), write (other changes), decide (approval decisions).
    scopes: Mapped[str] = mapped_column(String(64), default="read write decide",
                                        server_default="read write decide")


class LoginAttempt(Base):
    """Password checks (every route's), kept in the database so that rate limiting holds
    across server processes and replicas."""

    __tablename__ = "login_attempts"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    username: Mapped[str] = mapped_column(String(64), index=True)
    at: Mapped[datetime] = mapped_column(default=utcnow, index=True)
    # The client address, so that spraying one password over many accounts is limited too.
    address: Mapped[str | None] = mapped_column(String(64), default=None, index=True)
    # 'failed' from the moment it is recorded (before its hash is checked), 'ok' for a right
    # password, 'forgiven' for failures a later success ended: every row is one hash checked.
    outcome: Mapped[str] = mapped_column(String(8), default="failed", server_default="failed")


class VehicleProfile(Base):
    __tablename__ = "vehicles"
    id: Mapped[str] = mapped_column(String(100), primary_key=True)
    title: Mapped[str] = mapped_column(String(200), default="")
    profile: Mapped[dict[str, Any]]
    updated_at: Mapped[datetime] = mapped_column(default=utcnow)


class VehicleVersion(Base):
    """Every saved profile of a registry vehicle, numbered from 1; inserted, never changed, so
    an approval's profile can be compared with what the registry says now."""

    __tablename__ = "vehicle_versions"
    vehicle_id: Mapped[str] = mapped_column(String(100), primary_key=True)
    number: Mapped[int] = mapped_column(Integer, primary_key=True)
    title: Mapped[str] = mapped_column(String(200), default="")
    profile: Mapped[dict[str, Any]]
    saved_by: Mapped[str | None] = mapped_column(String(64), default=None)
    saved_at: Mapped[datetime] = mapped_column(default=utcnow)


class ChartRecord(Base):
    """A shared chart of the registry; the box makes the region query cheap."""

    __tablename__ = "charts"
    id: Mapped[str] = mapped_column(String(100), primary_key=True)
    title: Mapped[str] = mapped_column(String(200), default="")
    kind: Mapped[str] = mapped_column(String(32), default="other")
    chart: Mapped[dict[str, Any]]
    south: Mapped[float] = mapped_column(Float)
    west: Mapped[float] = mapped_column(Float)
    north: Mapped[float] = mapped_column(Float)
    east: Mapped[float] = mapped_column(Float)
    updated_at: Mapped[datetime] = mapped_column(default=utcnow)


class Mission(Base):
    """A mission and its editable draft head; `revision` is the draft's ETag."""

    __tablename__ = "missions"
    id: Mapped[str] = mapped_column(String(100), primary_key=True)
    title: Mapped[str] = mapped_column(String(500), default="")
    vehicle: Mapped[str | None] = mapped_column(String(100), default=None, index=True)
    status: Mapped[str] = mapped_column(String(16), default="draft", index=True)
    draft: Mapped[dict[str, Any]]
    draft_digest: Mapped[str] = mapped_column(String(71))
    layout: Mapped[dict[str, Any]] = mapped_column(default=dict)
    revision: Mapped[int] = mapped_column(Integer, default=1)
    created_by: Mapped[int] = mapped_column(ForeignKey("users.id"))
    created_at: Mapped[datetime] = mapped_column(default=utcnow)
    updated_by: Mapped[int] = mapped_column(ForeignKey("users.id"))
    updated_at: Mapped[datetime] = mapped_column(default=utcnow, index=True)
    # The open editing burst, logged as one event when it ends (store/draft_bursts.py).
    burst: Mapped[dict[str, Any] | None] = mapped_column(default=None)
    burst_at: Mapped[datetime | None] = mapped_column(default=None, index=True)
    # The list filters by status or vehicle and pages by id: one index range per page.
    __table_args__ = (Index("ix_missions_status_id", "status", "id"),
                      Index("ix_missions_vehicle_id", "vehicle", "id"))


class MissionVersion(Base):
    __tablename__ = "mission_versions"
    __table_args__ = (UniqueConstraint("mission_id", "number"),)
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    mission_id: Mapped[str] = mapped_column(ForeignKey("missions.id"), index=True)
    number: Mapped[int] = mapped_column(Integer)
    orders: Mapped[dict[str, Any]]
    digest: Mapped[str] = mapped_column(String(71), index=True)
    author_id: Mapped[int] = mapped_column(ForeignKey("users.id"))
    created_at: Mapped[datetime] = mapped_column(default=utcnow)


class ValidationReport(Base):
    """Reports are a pure function of the orders and the checks, so the key is the orders
    digest and the checker fingerprint (verify.fingerprint, `sha256:` and 64 hex digits)."""

    __tablename__ = "validation_reports"
    digest: Mapped[str] = mapped_column(String(71), primary_key=True)
    checker_version: Mapped[str] = mapped_column(String(71), primary_key=True)
    report: Mapped[dict[str, Any]]
    # What the mission list shows, written with the report so that a list never decodes
    # reports. Display only: submitting, reviewing and signing read `report`, so a
    # database writer who changes a count changes a number on a list and nothing else.
    ok: Mapped[bool | None] = mapped_column(Boolean, default=None)
    errors: Mapped[int | None] = mapped_column(Integer, default=None)
    warnings: Mapped[int | None] = mapped_column(Integer, default=None)
    created_at: Mapped[datetime] = mapped_column(default=utcnow)


class Submission(Base):
    __tablename__ = "submissions"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    version_id: Mapped[int] = mapped_column(ForeignKey("mission_versions.id"), index=True)
    state: Mapped[str] = mapped_column(String(16), default="submitted")
    submitted_by: Mapped[int] = mapped_column(ForeignKey("users.id"))
    submitted_at: Mapped[datetime] = mapped_column(default=utcnow)
    decided_by: Mapped[int | None] = mapped_column(ForeignKey("users.id"), default=None)
    decided_at: Mapped[datetime | None] = mapped_column(default=None)
    reason: Mapped[str] = mapped_column(Text, default="")
    # The stored rehearsal record the operator attached; the approval statement cites it.
    rehearsal_digest: Mapped[str | None] = mapped_column(
        ForeignKey("rehearsal_records.digest"), default=None)
    # One active submission per version, enforced by the database (migration 0005).
    __table_args__ = (
        Index("uq_submissions_active_version", "version_id", unique=True,
              sqlite_where=text("state IN ('submitted', 'approved')"),
              postgresql_where=text("state IN ('submitted', 'approved')")),
    )


class RehearsalRecord(Base):
    """A finished rehearsal: the record (outcomes, events, rule firings, energy) and viser's
    standalone HTML replay. Written once when the rehearsal stops; never changed."""

    __tablename__ = "rehearsal_records"
    digest: Mapped[str] = mapped_column(String(71), primary_key=True)
    mission_id: Mapped[str] = mapped_column(String(100), index=True)
    version: Mapped[int | None] = mapped_column(Integer, default=None)
    orders_digest: Mapped[str] = mapped_column(String(71), index=True)
    owner_id: Mapped[int] = mapped_column(ForeignKey("users.id"), index=True)
    source: Mapped[str] = mapped_column(String(16))
    record: Mapped[dict[str, Any]]
    replay_html: Mapped[bytes] = mapped_column(LargeBinary, deferred=True)
    replay_digest: Mapped[str] = mapped_column(String(71))
    event_id: Mapped[int] = mapped_column(ForeignKey("events.id"), unique=True)
    created_at: Mapped[datetime] = mapped_column(default=utcnow, index=True)


class Campaign(Base):
    """A rehearsal campaign: N seeded simulations of one set of orders over a sweep.
    `state` moves queued -> running -> finished | cancelled; `record` and `digest` are set once,
    when the last simulation is stored."""

    __tablename__ = "campaigns"
    id: Mapped[str] = mapped_column(String(32), primary_key=True)
    mission_id: Mapped[str | None] = mapped_column(String(100), default=None, index=True)
    version: Mapped[int | None] = mapped_column(Integer, default=None)
    orders_digest: Mapped[str] = mapped_column(String(71), index=True)
    orders: Mapped[dict[str, Any]]
    owner_id: Mapped[int | None] = mapped_column(ForeignKey("users.id"), default=None,
                                                 index=True)
    spec: Mapped[dict[str, Any]]
    simulations: Mapped[int] = mapped_column(Integer)
    state: Mapped[str] = mapped_column(String(16), default="queued", index=True)
    created_at: Mapped[datetime] = mapped_column(default=utcnow)
    ended_at: Mapped[datetime | None] = mapped_column(default=None)
    record: Mapped[dict[str, Any] | None] = mapped_column(default=None)
    # Not unique: the record is a pure function of the orders and the spec, so two people's
    # campaigns of the same spec seal the same record under the same digest.
    digest: Mapped[str | None] = mapped_column(String(71), default=None, index=True)


class CampaignRun(Base):
    """One simulation's result. At most one per (campaign, index), enforced by the database:
    a job retried after its worker died can never count a simulation twice."""

    __tablename__ = "campaign_runs"
    id: Mapped[int] = mapped_column(BigInteger().with_variant(Integer, "sqlite"),
                                    primary_key=True)
    campaign_id: Mapped[str] = mapped_column(ForeignKey("campaigns.id", ondelete="CASCADE"))
    index: Mapped[int] = mapped_column(Integer)
    result: Mapped[dict[str, Any]]
    __table_args__ = (UniqueConstraint("campaign_id", "index",
                                       name="uq_campaign_runs_campaign_index"),)


class CampaignAttachment(Base):
    """A finished campaign's record cited by a submission, beside its rehearsal record."""

    __tablename__ = "campaign_attachments"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    submission_id: Mapped[int] = mapped_column(ForeignKey("submissions.id"), index=True)
    campaign_id: Mapped[str] = mapped_column(ForeignKey("campaigns.id"))
    digest: Mapped[str] = mapped_column(String(71))
    attached_by: Mapped[int] = mapped_column(ForeignKey("users.id"))
    attached_at: Mapped[datetime] = mapped_column(default=utcnow)
    __table_args__ = (UniqueConstraint("submission_id", "campaign_id",
                                       name="uq_campaign_attachments_submission_campaign"),)


class Event(Base):
    """The append-only log of every state change."""

    __tablename__ = "events"
    id: Mapped[int] = mapped_column(BigInteger().with_variant(Integer, "sqlite"), primary_key=True)
    at: Mapped[datetime] = mapped_column(default=utcnow, index=True)
    actor_id: Mapped[int | None] = mapped_column(ForeignKey("users.id"), default=None)
    kind: Mapped[str] = mapped_column(String(64))
    mission_id: Mapped[str | None] = mapped_column(String(100), default=None, index=True)
    before_digest: Mapped[str | None] = mapped_column(String(71), default=None)
    after_digest: Mapped[str | None] = mapped_column(String(71), default=None)
    detail: Mapped[dict[str, Any]] = mapped_column(default=dict)
    # What the event is about ('user alice', 'mission m v2'), derived from the logged kind,
    # mission and detail (store/event_words.py) and kept for the activity log's filter.
    target: Mapped[str | None] = mapped_column(String(200), default=None, index=True)


class SigningKey(Base):
    """A supervisor's Ed25519 public key; `revoked_at` is the only column that ever changes."""

    __tablename__ = "signing_keys"
    id: Mapped[str] = mapped_column(String(64), primary_key=True)  # hex sha256 of the raw key
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id"), index=True)
    name: Mapped[str] = mapped_column(String(100), default="")
    public_key: Mapped[str] = mapped_column(String(64))
    created_at: Mapped[datetime] = mapped_column(default=utcnow)
    revoked_at: Mapped[datetime | None] = mapped_column(default=None)
    revoke_reason: Mapped[str] = mapped_column(Text, default="")


class Approval(Base):
    """A signed decision (approved, rejected, revoked), its DSSE envelope stored verbatim."""

    __tablename__ = "approvals"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    submission_id: Mapped[int] = mapped_column(ForeignKey("submissions.id"), index=True)
    version_id: Mapped[int] = mapped_column(ForeignKey("mission_versions.id"), index=True)
    mission_id: Mapped[str] = mapped_column(String(100), index=True)
    vehicle: Mapped[str | None] = mapped_column(String(100), default=None, index=True)
    author_id: Mapped[int] = mapped_column(ForeignKey("users.id"), index=True)
    decision: Mapped[str] = mapped_column(String(16), index=True)
    reason: Mapped[str] = mapped_column(Text, default="")
    revokes: Mapped[int | None] = mapped_column(ForeignKey("approvals.id"), default=None)
    supervisor_id: Mapped[int] = mapped_column(ForeignKey("users.id"), index=True)
    key_id: Mapped[str] = mapped_column(ForeignKey("signing_keys.id"))
    envelope: Mapped[str] = mapped_column(Text)
    envelope_digest: Mapped[str] = mapped_column(String(71))
    payload_digest: Mapped[str] = mapped_column(String(71), unique=True)
    orders_digest: Mapped[str] = mapped_column(String(71))
    event_id: Mapped[int] = mapped_column(ForeignKey("events.id"), unique=True)
    created_at: Mapped[datetime] = mapped_column(default=utcnow, index=True)
    # One decision and at most one revocation per submission (migration 0005).
    __table_args__ = (
        Index("uq_approvals_decision_submission", "submission_id", unique=True,
              sqlite_where=text("decision IN ('approved', 'rejected')"),
              postgresql_where=text("decision IN ('approved', 'rejected')")),
        Index("uq_approvals_revocation_submission", "submission_id", unique=True,
              sqlite_where=text("decision = 'revoked'"),
              postgresql_where=text("decision = 'revoked'")),
    )


class LogEntry(Base):
    """One leaf of the transparency log per event, hash-chained (approvals/log.py)."""

    __tablename__ = "log_entries"
    index: Mapped[int] = mapped_column(
        BigInteger().with_variant(Integer, "sqlite"), primary_key=True, autoincrement=False)
    event_id: Mapped[int] = mapped_column(ForeignKey("events.id"), unique=True)
    entry: Mapped[str] = mapped_column(Text)
    leaf_hash: Mapped[str] = mapped_column(String(64))


class Checkpoint(Base):
    """A signed statement of the log's size and Merkle root."""

    __tablename__ = "checkpoints"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    tree_size: Mapped[int] = mapped_column(BigInteger, index=True)
    root_hash: Mapped[str] = mapped_column(String(64))
    key_id: Mapped[str] = mapped_column(String(64))
    public_key: Mapped[str] = mapped_column(String(64))
    note: Mapped[str] = mapped_column(Text)
    signature: Mapped[str] = mapped_column(String(100))
    created_at: Mapped[datetime] = mapped_column(default=utcnow)


class LogReceipt(Base):
    """The log signer's receipt for one entry it appended (approvals/receipt.py)."""

    __tablename__ = "log_receipts"
    index: Mapped[int] = mapped_column(
        BigInteger().with_variant(Integer, "sqlite"), primary_key=True, autoincrement=False)
    receipt: Mapped[str] = mapped_column(Text)


class Cosignature(Base):
    """A witness's cosignature line over a checkpoint body (c2sp.org/tlog-cosignature)."""

    __tablename__ = "log_cosignatures"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    tree_size: Mapped[int] = mapped_column(BigInteger, index=True)
    body: Mapped[str] = mapped_column(Text)
    witness: Mapped[str] = mapped_column(String(200))
    line: Mapped[str] = mapped_column(Text)
    created_at: Mapped[datetime] = mapped_column(default=utcnow)


APPEND_ONLY_TABLES = ("events", "mission_versions", "approvals", "log_entries", "checkpoints")
# Made append-only by revision 0003 (0002 protects the tables above).
APPEND_ONLY_TABLES_0003 = ("rehearsal_records",)
# Made append-only by revision 0004.
APPEND_ONLY_TABLES_0004 = ("log_receipts", "log_cosignatures")


# The procedure library's tables live in their own module on this metadata.
from . import procedure_tables as procedure_tables  # noqa: E402
