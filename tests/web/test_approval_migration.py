"""Revision 0002 turns the events recorded before it into the first entries of the log."""

from __future__ import annotations

import json
from datetime import UTC, datetime

from alembic import command
from sqlalchemy import text

from countersign.approvals.log import GENESIS, entry_leaf
from countersign.store.db import Database, alembic_config
from countersign.store.events import record


def test_existing_events_are_backfilled_then_record_appends(database_url: str) -> None:
    database = Database(database_url)
    config = alembic_config(database_url)
    with database.engine.begin() as connection:
        config.attributes["connection"] = connection
        command.upgrade(config, "0001")
    with database.engine.begin() as connection:
        connection.execute(text(
            "INSERT INTO users (id, username, display_name, role, password_hash, disabled, "
            "created_at) VALUES (1, 'old', 'old', 'admin', 'x', false, :at)"),
            {"at": datetime(2026, 1, 1, tzinfo=UTC)})
        for number in range(3):
            connection.execute(text(
                "INSERT INTO events (at, actor_id, kind, mission_id, detail) VALUES "
                "(:at, 1, 'user.created', NULL, :detail)"),
                {"at": datetime(2026, 1, 1, number, tzinfo=UTC),
                 "detail": json.dumps({"n": number})})
    database.migrate()
    with database.session() as db:
        record(db, kind="after.migration", actor=None, signer=database.log_signer)
    with database.engine.connect() as connection:
        rows = connection.execute(text(
            'SELECT "index", entry, leaf_hash FROM log_entries ORDER BY "index"')).all()
    assert [r[0] for r in rows] == [0, 1, 2, 3]
    prev = GENESIS
    for index, entry, leaf in rows:
        data = json.loads(entry)
        assert data["index"] == index and data["prev"] == prev
        assert entry_leaf(entry.encode()) == leaf
        prev = leaf
    first = json.loads(rows[0][1])["event"]
    assert first["actor"] == "old" and first["at"] == "2026-01-01T00:00:00Z"
    assert first["detail"] == {"n": 0}
    database.engine.dispose()
