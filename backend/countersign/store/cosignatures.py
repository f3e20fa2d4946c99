"""Witness cosignatures of checkpoints (c2sp.org/tlog-cosignature): accepted when they verify
under a witness key the server's administrator listed (the `witnesses` file beside the log key,
one `name+hash+key` verifier key per line), kept append-only and published with the
checkpoint."""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.dsse import SignatureError
from ..approvals.note import (
    COSIGNATURE,
    cosignature_time,
    parse_body,
    parse_verifier_key,
    verify_cosignature,
)
from ..errors import Invalid
from ..limits import CLOCK_SKEW
from .missions import NotFound
from .tables import Checkpoint, Cosignature

WITNESSES_FILE = "witnesses"


class BadCosignature(Invalid):
    pass


def witness_keys(directory: Path) -> dict[str, bytes]:
    """The registered witnesses: name to raw Ed25519 public key (lines starting # ignored)."""
    try:
        lines = (directory / WITNESSES_FILE).read_text().splitlines()
    except FileNotFoundError:
        return {}
    keys: dict[str, bytes] = {}
    for line in lines:
        if line.strip() and not line.startswith("#"):
            name, kind, raw = parse_verifier_key(line)
            if kind == COSIGNATURE:
                keys[name] = raw
    return keys


def add_cosignature(db: DbSession, *, directory: Path, body: str, line: str) -> Cosignature:
    try:
        head = parse_body(body)
    except SignatureError as exc:
        raise BadCosignature(f"checkpoint: {exc}") from None
    if not line.endswith("\n"):
        line += "\n"
    name = line.split(" ")[1] if line.count(" ") >= 2 else ""
    keys = witness_keys(directory)
    if name not in keys:
        raise BadCosignature(f"cosignature: {name!r} is not a registered witness (the "
                             f"administrator lists witness keys in {directory / WITNESSES_FILE})")
    rows = db.scalars(select(Checkpoint).where(Checkpoint.tree_size == head.size))
    if not any(r.note.startswith(body + "\n") or r.note == body for r in rows):
        raise NotFound(f"the log signed no checkpoint with this body (size {head.size})")
    try:
        signed_at = verify_cosignature(line, body, name, keys[name])
    except (SignatureError, ValueError) as exc:
        raise BadCosignature(f"cosignature: {exc}") from None
    _check_time(db, body=body, witness=name, signed_at=signed_at)
    row = Cosignature(tree_size=head.size, body=body, witness=name, line=line)
    db.add(row)
    db.flush()
    return row


def _check_time(db: DbSession, *, body: str, witness: str, signed_at: int) -> None:
    # A witness's clock only moves forward: a replayed older (still valid) cosignature must not
    # replace the newer one that is published, and a time beyond our clock is not yet a claim.
    latest = (datetime.now(UTC) + CLOCK_SKEW).timestamp()
    if signed_at > latest:
        raise BadCosignature(f"cosignature: witness {witness} dated it {signed_at}, later than "
                             f"this server's clock allows (now + {CLOCK_SKEW})")
    for stored in db.scalars(select(Cosignature.line).where(
            Cosignature.body == body, Cosignature.witness == witness)):
        stored_at = cosignature_time(stored, body)
        if stored_at >= signed_at:
            raise BadCosignature(f"cosignature: witness {witness} already cosigned this "
                                 f"checkpoint at {stored_at}; only a "
                                 "later cosignature replaces it")


def cosignature_lines(db: DbSession, body: str) -> list[str]:
    """The published cosignature lines over this checkpoint body, one per witness (newest)."""
    lines: dict[str, str] = {}
    for row in db.scalars(select(Cosignature).where(Cosignature.body == body)
                          .order_by(Cosignature.id)):
        lines[row.witness] = row.line
    return list(lines.values())
