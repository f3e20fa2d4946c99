"""Adoption of a log appended before receipts existed (an upgraded deployment).

The log signer vouches only for entries carrying its receipt, so a log whose entries all
predate receipts would be refused forever. Adoption issues receipts for those entries, once,
and only when nothing else can explain their lack of receipts:

* this process start made the signer's key (or imported the legacy key), and the signer has
  no state file: no head was ever signed from this directory;
* the database holds log entries but no receipt at all: had receipts ever been issued, an
  entry without one was written behind the app's back, and the refusal must stand;
* every checkpoint in the database signed by this key still matches the log.

The adoption is itself a log entry (`log.adopted`: how many entries, their root), so the
bundle and its verifiers say which entries were adopted; the signer's state records the
adopted size too. The first checkpoint then covers them all."""

from __future__ import annotations

import sys

from sqlalchemy import func, select, text

from ..approvals.dsse import public_text
from ..approvals.signer import LogSigner
from .approvals.log import _checkpoint_now, _committed_tree
from .db import Database
from .events import LOG_LOCK, record
from .tables import Checkpoint, LogEntry, LogReceipt, utcnow

ADOPTED = "log.adopted"


def adopt_pre_receipt_log(database: Database, signer: LogSigner) -> int | None:
    """Adopt the log if it is safe (see the module); the number of entries adopted, or None."""
    if not signer.fresh or signer.has_state():
        return None
    with database.session() as db:
        if db.get_bind().dialect.name == "postgresql":
            # No entry is appended while the log is looked at and adopted.
            db.execute(text("SELECT pg_advisory_xact_lock(:key)"), {"key": LOG_LOCK})
        if db.scalar(select(func.count()).select_from(LogReceipt)):
            return None
        rows = db.execute(select(LogEntry.index, LogEntry.leaf_hash)
                          .order_by(LogEntry.index)).all()
        if not rows:
            return None
        tree = _committed_tree(db)
        if tree.size != len(rows):
            return None  # entries appended since this transaction began
        own = public_text(signer.key)
        for checkpoint in db.scalars(select(Checkpoint).where(Checkpoint.public_key == own)):
            if checkpoint.tree_size > tree.size or \
                    tree.root(checkpoint.tree_size).hex() != checkpoint.root_hash:
                sys.stderr.write(f"countersign: the log is not adopted: it differs from the "
                                 f"checkpoint its key signed at size {checkpoint.tree_size}\n")
                return None
        time = utcnow().isoformat().replace("+00:00", "Z")
        for index, leaf in rows:
            db.add(LogReceipt(index=index, receipt=signer.receipt(index, leaf, time)))
        db.flush()
        record(db, signer=signer, kind=ADOPTED, actor=None, detail={
            "entries": len(rows), "root": tree.root().hex(), "key_id": signer.key_id,
            "legacy_key": signer.imported is not None})
    adopted = len(rows)
    with database.session() as db:
        _checkpoint_now(db, signer, adopted=adopted)
    sys.stderr.write(f"countersign: adopted the {adopted} log entries appended before receipts "
                     f"existed (log entry {adopted} records it); checkpoints are signed again\n")
    return adopted
