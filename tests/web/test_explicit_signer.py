"""The event log's receipts come from the signer a caller gives `record()`, never from what
the session or its database happens to hold: a session of a database without a signer still
receipts with the given one, and a caller that gives none gets no receipt even beside a
database that has a signer."""

from __future__ import annotations

from sqlalchemy import select

from countersign.store.db import Database
from countersign.store.events import record
from countersign.store.tables import LogEntry, LogReceipt

from .conftest import World


def test_the_given_signer_receipts_the_entry(world: World) -> None:
    signer = world.database.log_signer
    assert signer is not None
    bare = Database(world.database.url)  # opened by a tool: no signer of its own
    assert bare.log_signer is None
    try:
        with bare.session() as db:
            event = record(db, signer=signer, kind="test.given", actor=None)
            index = db.scalar(select(LogEntry.index).where(LogEntry.event_id == event.id))
            assert index is not None
            assert db.get(LogReceipt, index) is not None
    finally:
        bare.engine.dispose()
    # Told after the commit, so that it never signs a head without the entry.
    assert index in signer.remembered_beyond(index)


def test_no_signer_given_no_receipt(world: World) -> None:
    with world.database.session() as db:
        event = record(db, signer=None, kind="test.unsigned", actor=None)
        index = db.scalar(select(LogEntry.index).where(LogEntry.event_id == event.id))
        assert index is not None
        assert db.get(LogReceipt, index) is None
