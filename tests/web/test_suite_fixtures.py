"""The suite's own speed-ups keep their promises: cheap Argon2 only under test
and never for the tests that count or inspect the real hasher; each world starts from the
session's migrated template, which is as empty as a freshly migrated database; the quick loop's
markers follow folders and fixtures."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from argon2 import extract_parameters
from argon2.profiles import CHEAPEST
from sqlalchemy import text

from countersign.store import accounts, login_throttle
from countersign.store.db import Database
from countersign.store.hashing import BoundedHasher

from .. import markers
from ..cheap_hashing import PRODUCTION_HASHER
from ..db_template import (
    STAMP,
    STAMP_COMMENT,
    PostgresTemplate,
    SqliteTemplate,
    postgres_stamp,
    sqlite_stamp,
)
from .conftest import OPEN_TRANSACTIONS, PASSWORD, World, count_rows, seed_users, watched

TESTS = Path(__file__).resolve().parents[1]


def _stored_memory_costs(world: World) -> set[int]:
    with world.database.engine.connect() as connection:
        hashes = connection.execute(text("SELECT password_hash FROM users")).scalars().all()
    return {extract_parameters(h).memory_cost for h in hashes}


def _hashers() -> tuple[object, object]:
    """The hasher sign-in (the throttle) and account creation call now."""
    return vars(login_throttle)["HASHER"], vars(accounts)["HASHER"]


def test_the_world_hashes_with_cheap_parameters(world: World) -> None:
    assert _stored_memory_costs(world) == {CHEAPEST.memory_cost}
    throttle, creation = _hashers()
    assert throttle is creation is not PRODUCTION_HASHER
    # An unknown username costs what a wrong password does, as in production.
    assert extract_parameters(accounts._DUMMY_HASH).memory_cost == CHEAPEST.memory_cost
    # Production's hasher is untouched: argon2-cffi's defaults, as `countersign serve` has them.
    assert PRODUCTION_HASHER.memory_cost == BoundedHasher().memory_cost > CHEAPEST.memory_cost


@pytest.mark.production_hashing
def test_a_marked_test_hashes_as_production_does(world: World) -> None:
    assert _hashers() == (PRODUCTION_HASHER, PRODUCTION_HASHER)
    assert _stored_memory_costs(world) == {PRODUCTION_HASHER.memory_cost}


def test_modules_that_patch_the_hasher_keep_production_hashing() -> None:
    """A test that counts or probes hashes at HASHER patches the production object: without
    the marker, sign-in would call the cheap one and the count would silently be zero."""
    patching = re.compile(r"setattr\(\s*HASHER\b")
    unmarked = [str(path.relative_to(TESTS)) for path in sorted(TESTS.rglob("test_*.py"))
                if patching.search(source := path.read_text(encoding="utf-8"))
                and "production_hashing" not in source]
    assert unmarked == []


def test_the_world_starts_from_the_sessions_template(world: World) -> None:
    engine = world.database.engine
    if engine.dialect.name == "sqlite":
        assert engine.url.database
        assert sqlite_stamp(Path(engine.url.database)) == STAMP
    else:
        with engine.connect() as connection:
            assert postgres_stamp(connection) == STAMP_COMMENT


def _table_counts(database: Database) -> dict[str, int]:
    with database.engine.connect() as connection:
        if database.engine.dialect.name == "sqlite":
            names = connection.execute(text(
                "SELECT name FROM sqlite_master WHERE type = 'table' "
                "AND name NOT LIKE 'sqlite_%'")).scalars().all()
        else:
            names = connection.execute(text(
                "SELECT tablename FROM pg_tables WHERE schemaname = 'public'")).scalars().all()
    return {name: count_rows(database, f'SELECT count(*) FROM "{name}"') for name in names}


def test_a_template_database_holds_what_migration_leaves(world: World, tmp_path: Path,
                                                         request: pytest.FixtureRequest) -> None:
    """Nothing but the Alembic revision; on PostgreSQL after a test wrote (the world's users and
    mission), with ids from 1 again."""
    if world.database.engine.dialect.name == "sqlite":
        template = request.getfixturevalue("sqlite_template")
        database = Database(f"sqlite:///{tmp_path / 'again.db'}")
        template.copy_to(tmp_path / "again.db")
    else:
        assert count_rows(world.database, "SELECT count(*) FROM users") == 4
        world.database.engine.dispose()
        postgres: PostgresTemplate = request.getfixturevalue("postgres_template")
        rebuilds = postgres.rebuilds
        postgres.reset()
        assert postgres.rebuilds == rebuilds  # emptied, not migrated again
        # A new Database: the world's log signer remembers the entries the reset erased.
        database = Database(world.database.url)
    counts = _table_counts(database)
    assert len(counts) > 20 and counts.pop("alembic_version") == 1
    assert {name: n for name, n in counts.items() if n} == {}
    with database.session() as db:
        user = accounts.create_user(db, username="first", role="auditor",
                                    password="a long password 1", signer=database.log_signer)
        assert user.id == 1
    database.engine.dispose()


def test_a_disabled_trigger_is_restored_by_the_next_reset(world: World,
                                                         request: pytest.FixtureRequest) -> None:
    """Tamper tests switch the append-only triggers off to play a database writer; the next
    test must again find a log that refuses updates (the reset migrates afresh)."""
    if world.database.engine.dialect.name == "sqlite":
        pytest.skip("SQLite worlds are fresh copies of the template file")
    world.database.engine.dispose()
    postgres: PostgresTemplate = request.getfixturevalue("postgres_template")
    with postgres.engine.begin() as connection:
        connection.execute(text("ALTER TABLE log_entries DISABLE TRIGGER USER"))
    rebuilds = postgres.rebuilds
    postgres.reset()
    assert postgres.rebuilds == rebuilds + 1
    with postgres.engine.connect() as connection:
        enabled = connection.execute(text(
            "SELECT bool_and(tgenabled <> 'D') FROM pg_trigger "
            "WHERE tgrelid = 'log_entries'::regclass AND NOT tgisinternal")).scalar_one()
    assert enabled


@dataclass
class _Item:
    """What tests/markers.py reads of a collected test."""

    path: Path
    fixturenames: tuple[str, ...] = ()
    callspec: object = None
    markers: list[str] = field(default_factory=list)

    def add_marker(self, marker: pytest.MarkDecorator) -> None:
        self.markers.append(marker.name)


@dataclass
class _Callspec:
    params: dict[str, object]


def test_markers_follow_folders_and_fixtures(request: pytest.FixtureRequest) -> None:
    items = [_Item(TESTS / "e2e" / "test_editor.py"),
             _Item(TESTS / "web" / "test_roles.py", ("database_url",),
                   _Callspec({"database_url": "postgresql"})),
             _Item(TESTS / "web" / "test_roles.py", ("database_url",),
                   _Callspec({"database_url": "sqlite"})),
             _Item(TESTS / "campaigns" / "test_campaign_kill.py", ("postgres",)),
             _Item(TESTS / "web" / "test_fuzz.py")]
    markers.mark_items(items)  # type: ignore[arg-type]
    assert [item.markers for item in items] == [
        ["browser"], ["postgres"], [], ["slow", "postgres"], ["slow"]]
    registered = {line.split(":", 1)[0] for line in request.config.getini("markers")}
    assert {"browser", "postgres", "slow", "production_hashing"} <= registered


def _refuse_hashing(*args: object, **kwargs: object) -> str:
    raise AssertionError("a seeded world hashed a password again")


@pytest.mark.production_hashing
def test_seeded_worlds_share_the_sessions_production_hashes(
        sqlite_template: SqliteTemplate, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    stored = []
    for name in ("first", "second"):
        path = tmp_path / f"{name}.db"
        sqlite_template.copy_to(path)
        database = Database(f"sqlite:///{path}")
        if name == "second":
            monkeypatch.setattr(PRODUCTION_HASHER, "hash", _refuse_hashing)
        seed_users(database)
        with database.engine.connect() as connection:
            stored.append(connection.execute(text(
                "SELECT password_hash FROM users ORDER BY id")).scalars().all())
        database.engine.dispose()
    monkeypatch.undo()
    assert stored[0] == stored[1] and len(set(stored[0])) == len(stored[0]) == 4
    assert {extract_parameters(h).memory_cost for h in stored[0]} == {
        PRODUCTION_HASHER.memory_cost}
    assert all(PRODUCTION_HASHER.verify(h, PASSWORD) for h in stored[0])


def test_a_transaction_left_open_is_seen(database_url: str,
                                         request: pytest.FixtureRequest) -> None:
    """The guard that fails a test leaving a PostgreSQL transaction open (conftest.py,
    no_transaction_left_open) looks after this test, and its query finds such a connection."""
    if not database_url.startswith("postgresql"):
        pytest.skip("the guard reads PostgreSQL's pg_stat_activity")
    assert watched(request.node)
    template: PostgresTemplate = request.getfixturevalue("postgres_template")
    database = Database(database_url)
    left = database.engine.connect()
    try:
        pid = left.execute(text("SELECT pg_backend_pid()")).scalar_one()
        with template.engine.connect() as connection:
            found = [row[0] for row in connection.execute(OPEN_TRANSACTIONS)]
        assert pid in found
    finally:
        left.close()
        database.engine.dispose()
