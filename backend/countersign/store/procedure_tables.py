"""The procedure library's tables, on the one metadata of store/tables.py.

Both tables are only ever inserted into. A row's digest, its document and its decision are
checked against the log entry that recorded it (store/procedures.py): a database writer who is
not the app changes them in vain."""

from __future__ import annotations

from datetime import datetime
from typing import Any

from sqlalchemy import ForeignKey, Integer, String, Text, UniqueConstraint
from sqlalchemy.orm import Mapped, mapped_column

from .tables import Base, utcnow


class ProcedureRecord(Base):
    """One saved version of a procedure; immutable (a change is a new version)."""

    __tablename__ = "procedures"
    name: Mapped[str] = mapped_column(String(100), primary_key=True)
    version: Mapped[int] = mapped_column(Integer, primary_key=True)
    document: Mapped[dict[str, Any]]
    digest: Mapped[str] = mapped_column(String(71))
    author_id: Mapped[int] = mapped_column(ForeignKey("users.id"), index=True)
    event_id: Mapped[int] = mapped_column(ForeignKey("events.id"), unique=True)
    # When it was saved (never changes); named as the registry's tables name it, so that the
    # registry stamp (store/vehicles.py) reads it the same way.
    updated_at: Mapped[datetime] = mapped_column(default=utcnow)


class ProcedureApproval(Base):
    """A supervisor's signed decision on one procedure version, its DSSE envelope verbatim."""

    __tablename__ = "procedure_approvals"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    name: Mapped[str] = mapped_column(String(100), index=True)
    version: Mapped[int] = mapped_column(Integer)
    procedure_digest: Mapped[str] = mapped_column(String(71))
    decision: Mapped[str] = mapped_column(String(16))
    reason: Mapped[str] = mapped_column(Text, default="")
    supervisor_id: Mapped[int] = mapped_column(ForeignKey("users.id"), index=True)
    key_id: Mapped[str] = mapped_column(ForeignKey("signing_keys.id"))
    envelope: Mapped[str] = mapped_column(Text)
    payload_digest: Mapped[str] = mapped_column(String(71), unique=True)
    event_id: Mapped[int] = mapped_column(ForeignKey("events.id"), unique=True)
    created_at: Mapped[datetime] = mapped_column(default=utcnow)
    # One decision per version: a parallel second one fails at the insert.
    __table_args__ = (UniqueConstraint("name", "version",
                                       name="uq_procedure_approvals_name_version"),)
