"""The decision guard's roles come from the log, not the users table.

A database writer can `UPDATE users SET role = 'supervisor'`; the users table is then no
evidence. The account entries of the log (creation with a role, role changes, disabling,
resets), each receipted by the log signer, are replayed with the verifiers' own rule
(approvals/role_rules.py), so the app refuses exactly the decisions `countersign audit verify`
and the browser would name. An account entry without a valid receipt fails closed: a deleted
receipt must not hide a demotion, nor a forged entry grant a role."""

from __future__ import annotations

import json
from functools import lru_cache
from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.dsse import SignatureError, public_key
from ..approvals.log import entry_leaf
from ..approvals.receipt import verify_receipt
from ..approvals.role_rules import RoleBook, replay
from ..approvals.signer import LogSigner
from .tables import LogEntry, LogReceipt, User

# RFC 8785 entries: an account event's kind is written exactly so (a quote inside a string
# would be escaped); the match is confirmed by parsing.
_ACCOUNT_LIKE = '%"kind":"user.%'


def _account_entries(db: DbSession, signer: LogSigner | None
                     ) -> tuple[list[tuple[int, dict[str, Any]]], str | None]:
    """The log's account events in log order, and why they cannot be trusted (None when
    every one carries the log signer's receipt, or when no signer is given)."""
    rows = db.execute(select(LogEntry.index, LogEntry.entry, LogEntry.leaf_hash,
                             LogReceipt.receipt)
                      .outerjoin(LogReceipt, LogReceipt.index == LogEntry.index)
                      .where(LogEntry.entry.like(_ACCOUNT_LIKE)).order_by(LogEntry.index))
    found: list[tuple[int, dict[str, Any]]] = []
    for index, text, leaf, receipt in rows:
        try:
            event = json.loads(text)["event"]
        except (ValueError, KeyError, TypeError):
            return found, f"log entry {index} is not a log entry the app wrote"
        if not isinstance(event, dict) or not str(event.get("kind", "")).startswith("user."):
            continue
        if signer is not None:
            why = _unvouched(signer.public_text, signer.origin, int(index), text, leaf, receipt)
            if why is not None:
                return found, f"log entry {index} ({event.get('kind')}) {why}"
        found.append((int(index), event))
    return found, None


@lru_cache(maxsize=8192)  # account entries only: bounded memory
def _unvouched(public: str, origin: str, index: int, text: str, leaf: str,
               receipt: str | None) -> str | None:
    """Why the signer does not vouch for this entry (None when it does). Entries never
    change, so a check is remembered by its inputs: a review page then verifies only the
    account entries appended since (an Ed25519 check per entry and request added up)."""
    try:
        if entry_leaf(text.encode()) != leaf:
            raise SignatureError("does not hash to its leaf")
        verify_receipt(receipt, index=index, leaf=leaf, origin=origin, key=public_key(public))
    except SignatureError as exc:
        return str(exc)
    return None


def logged_roles(db: DbSession, *, signer: LogSigner | None) -> tuple[RoleBook, str | None]:
    entries, untrusted = _account_entries(db, signer)
    return replay(entries), untrusted


def decision_refusal_from_log(db: DbSession, user: User, *,
                              signer: LogSigner | None) -> str | None:
    """Why the log does not let this user decide (None when it does), naming how the users
    table disagrees."""
    book, untrusted = logged_roles(db, signer=signer)
    if untrusted is not None:
        return (f"roles cannot be read from the log: {untrusted}; no decision until the log "
                "is restored")
    why = book.decision_problem(user.username)
    if why is None:
        return None
    return (f"the users table says {user.username} is {user.role}, but {why}: a role changed "
            "outside the app is not trusted, and only a supervisor by the log decides")
