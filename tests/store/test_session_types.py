"""Read and write sessions are distinct types: what a session may do is its type, not a flag in
its `info` (store/db.py, `writes`)."""

from __future__ import annotations

from pathlib import Path

import pytest
from sqlalchemy.orm import Session

from countersign.store.db import Database, ReadSession, WriteSession, writable, writes


@pytest.fixture
def database(tmp_path: Path) -> Database:
    return Database(f"sqlite:///{tmp_path / 'types.db'}")


def test_each_way_of_opening_gives_its_type(database: Database) -> None:
    with database.session(write=False) as reader, database.session() as writer:
        assert isinstance(reader, ReadSession) and not writes(reader)
        assert isinstance(writer, WriteSession) and writes(writer)
    with database.open(write=False) as reader, database.open() as writer:
        assert isinstance(reader, ReadSession) and not writes(reader)
        assert isinstance(writer, WriteSession) and writes(writer)
    database.engine.dispose()


def test_a_plain_session_writes_and_a_reader_writes_through_a_session_of_its_own(
        database: Database) -> None:
    with Session(database.engine) as plain:
        assert writes(plain)
    with database.session(write=False) as reader, writable(reader) as writer:
        assert writer is not reader and isinstance(writer, WriteSession)
    database.engine.dispose()
