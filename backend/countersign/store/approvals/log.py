"""The transparency log: its Merkle tree (cached by the database), checkpoints, proofs."""

from __future__ import annotations

from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ...approvals import dsse
from ...approvals.merkle import Tree
from ...approvals.note import signature_line
from ...approvals.signer import LogSigner, SignerRefused
from ...errors import Conflict, Unavailable
from ..db import BEGIN_MODE, LogTreeCache, log_trees_of, writes
from ..log_gaps import missing_entries
from ..missions import NotFound
from ..tables import (
    Approval,
    Checkpoint,
    LogEntry,
    LogReceipt,
)


class LogUnvouched(Unavailable):
    """The log signer refused to vouch for the log as the database holds it."""


def _checkpoint_now(db: DbSession, signer: LogSigner, *,
                    adopted: int | None = None) -> tuple[Checkpoint | None, str | None]:
    """The checkpoint of the committed log, signed now unless the latest one covers it, and
    why the signer refused to sign a newer one (None when it did not refuse). Only committed
    entries are signed, so a signed head is never rolled back with a failed transaction.
    A read-only session signs through a short write session."""
    if not writes(db):
        from ..db import database_of

        with database_of(db).session() as writer:
            return _checkpoint_now(writer, signer, adopted=adopted)
    tree = _committed_tree(db)
    latest = db.scalar(select(Checkpoint).where(Checkpoint.tree_size <= tree.size)
                       .order_by(Checkpoint.tree_size.desc()).limit(1))
    erased = _erased_entry(db, signer, tree)
    if erased is not None:
        return latest, erased
    if tree.size == 0 or (latest is not None and latest.tree_size == tree.size):
        return latest, None
    head = signer.head()
    if tree.size < head.size:
        # Another process signed a newer head that this snapshot does not see yet.
        return latest, None
    receipts = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt).where(
        LogReceipt.index >= head.size, LogReceipt.index < tree.size)).all())
    try:
        signed = signer.sign_head(tree, receipts, adopted)
    except SignerRefused as exc:
        return latest, str(exc)
    row = Checkpoint(tree_size=tree.size, root_hash=signed["root"], key_id=signed["key_id"],
                     public_key=signed["public_key"], note=signed["signed_note"],
                     signature=signed["signature"])
    db.add(row)
    db.flush()
    return row, None


def _erased_entry(db: DbSession, signer: LogSigner, tree: Tree) -> str | None:
    """Why the log lacks a committed entry the signer remembers appending (None when it
    lacks none): one replaced within this tree, or one past its end that a fresh read of
    the log does not hold either (a snapshot older than a concurrent commit is no loss)."""
    replaced = signer.replaced(tree)
    if replaced is not None:
        return replaced
    beyond = signer.remembered_beyond(tree.size)
    if not beyond:
        return None
    from ..db import database_of

    with database_of(db).session(write=False) as fresh:
        held = dict(fresh.execute(select(LogEntry.index, LogEntry.leaf_hash).where(
            LogEntry.index.in_(list(beyond)))).all())
    for index, leaf in sorted(beyond.items()):
        if held.get(index) != leaf:
            return (f"log entry {index} ({leaf[:16]}...) was appended and committed, but the "
                    "log no longer holds it: an entry was deleted")
    return None


def vouched_checkpoint(db: DbSession, *, signer: LogSigner) -> Checkpoint:
    """The checkpoint of the committed log, refused (LogUnvouched) whenever the signer
    refuses the log as it stands: what is built on it (a package) must not rest on a head
    the signer no longer vouches for as the log's state."""
    row, refusal = _checkpoint_now(db, signer)
    if row is None or refusal is not None:
        raise LogUnvouched(refusal or "the log has no signed checkpoint yet")
    return row


def receipt_of(db: DbSession, approval: Approval) -> str | None:
    """The log signer's receipt for the approval's log entry."""
    index = log_index_of(db, approval.event_id)
    return None if index is None else db.scalar(
        select(LogReceipt.receipt).where(LogReceipt.index == index))


def _leaf(index: int, leaf_hash: str) -> bytes:
    # The app writes 64 hex digits; anything else came from a writer that is not the app, and
    # was a 500 (ValueError) on every route that builds the tree.
    try:
        leaf = bytes.fromhex(leaf_hash)
    except ValueError:
        leaf = b""
    if len(leaf) != 32:
        raise Conflict(f"the log was altered outside the app: log entry {index} has a "
                       "malformed leaf hash")
    return leaf


def _committed_tree(db: DbSession) -> Tree:
    """The committed log as a Merkle tree, cached by the Database object and extended
    incrementally.
    The log only grows: one query returns the last cached leaf (to check that the cache still
    matches the database; otherwise it is rebuilt) and any newer leaves. Cached trees are never
    mutated, only replaced, so concurrent readers may share them."""
    engine = db.get_bind().engine
    cache = log_trees_of(db) or LogTreeCache()
    cached = cache.tree
    with engine.connect() as opened:
        # A reader of committed rows: never ask for SQLite's write lock (this request may hold it).
        connection = opened.execution_options(**{BEGIN_MODE: "DEFERRED"})
        since = cached.size - 1 if cached is not None and cached.size else 0
        rows = connection.execute(select(LogEntry.index, LogEntry.leaf_hash).where(
            LogEntry.index >= since).order_by(LogEntry.index)).all()
        if cached is not None and cached.size:
            if not rows or rows[0][0] != since or _leaf(*rows[0]) != cached.levels[0][-1]:
                cached, since = None, 0
                rows = connection.execute(select(LogEntry.index, LogEntry.leaf_hash)
                                          .order_by(LogEntry.index)).all()
            else:
                rows = rows[1:]
        if cached is not None and not rows:
            return cached
        tree = cached.copy() if cached is not None else Tree()
        for index, leaf in rows:
            tree.append(_leaf(index, leaf))
    with cache.lock:
        current = cache.tree
        if current is None or current.size <= tree.size:
            cache.tree = tree
    return tree


def log_tree(db: DbSession, *, pending: bool = False) -> Tree:
    """The log's tree; with `pending`, including entries this transaction appended."""
    tree = _committed_tree(db)
    if pending:
        rows = db.execute(select(LogEntry.index, LogEntry.leaf_hash)
                          .where(LogEntry.index >= tree.size).order_by(LogEntry.index)).all()
        if rows:
            tree = tree.copy()
            for index, leaf in rows:
                tree.append(_leaf(index, leaf))
    return tree


def latest_checkpoint(db: DbSession, *, signer: LogSigner) -> Checkpoint:
    row, refusal = _checkpoint_now(db, signer)
    if row is None:
        raise LogUnvouched(refusal or "the log has no signed checkpoint yet")
    return row


def checkpoint_refusal(db: DbSession, *, signer: LogSigner) -> str | None:
    """Why the signer will not sign the log's current head (None when it signs)."""
    return _checkpoint_now(db, signer)[1]


def checkpoint_json(row: Checkpoint, cosignatures: list[str] | None = None) -> dict[str, Any]:
    body, signed = row.note, row.note
    if "\n\n" in row.note:  # a signed note (older rows hold only the body)
        body = row.note.split("\n\n", 1)[0] + "\n"
    else:
        signed = legacy_signed_note(row)
    if cosignatures:
        signed = signed + "".join(cosignatures)
    return {"size": row.tree_size, "root": row.root_hash, "note": body, "signed_note": signed,
            "origin": body.split("\n", 1)[0], "key_id": row.key_id,
            "public_key": row.public_key, "signature": row.signature,
            "created_at": row.created_at.isoformat()}


def legacy_signed_note(row: Checkpoint) -> str:
    """The signed note of a checkpoint signed before checkpoints were signed notes: its
    signature is the log key's Ed25519 signature over the body, which is what a note's
    signature line carries (so the old checkpoint verifies as a note, under its origin)."""
    origin = row.note.split("\n", 1)[0]
    try:
        public = dsse.raw_public(dsse.public_key(row.public_key))
        signature = dsse.unb64(row.signature, "the checkpoint signature")
    except dsse.SignatureError:
        return row.note  # left for the verifier to refuse
    return row.note + "\n" + signature_line(origin, public, signature)


def _whole_tree(db: DbSession) -> Tree:
    # With entries deleted behind the app's back the remaining leaves sit at the wrong
    # positions: a proof over them matches no signed checkpoint, so none is given.
    gaps = missing_entries(db)
    if gaps:
        runs = ", ".join(f"log entry {a}" if a == b else f"log entries {a}..{b}"
                         for a, b in gaps)
        raise Conflict(f"the log was altered outside the app: {runs} missing; no proof "
                       "until it is restored")
    return _committed_tree(db)


def inclusion_proof(db: DbSession, *, index: int, size: int | None = None) -> dict[str, Any]:
    tree = _whole_tree(db)
    size = tree.size if size is None else size
    if not 0 <= index < size <= tree.size:
        raise NotFound(f"no log entry {index} in a tree of size {size} (the log has "
                       f"{tree.size} entries)")
    return {"index": index, "size": size, "leaf_hash": tree.levels[0][index].hex(),
            "root": tree.root(size).hex(),
            "hashes": [h.hex() for h in tree.inclusion_proof(index, size)]}


def consistency_proof(db: DbSession, *, first: int, second: int | None = None) -> dict[str, Any]:
    tree = _whole_tree(db)
    second = tree.size if second is None else second
    if not 0 < first <= second <= tree.size:
        raise NotFound(f"no consistency proof from size {first} to {second} (the log has "
                       f"{tree.size} entries)")
    return {"first": first, "second": second, "first_root": tree.root(first).hex(),
            "second_root": tree.root(second).hex(),
            "hashes": [h.hex() for h in tree.consistency_proof(first, second)]}


def log_index_of(db: DbSession, event_id: int) -> int | None:
    return db.scalar(select(LogEntry.index).where(LogEntry.event_id == event_id))


def entries(db: DbSession, *, start: int, limit: int) -> list[dict[str, Any]]:
    rows = list(db.scalars(select(LogEntry).where(LogEntry.index >= start)
                           .order_by(LogEntry.index).limit(limit)))
    receipts = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt).where(
        LogReceipt.index.in_([r.index for r in rows]))).all()) if rows else {}
    return [{"index": r.index, "leaf_hash": r.leaf_hash, "entry": r.entry,
             "receipt": receipts.get(r.index)} for r in rows]


def _receipts(db: DbSession, size: int) -> list[str | None]:
    found = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt)).all())
    return [found.get(i) for i in range(size)]
