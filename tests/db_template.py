"""A database migrated once per test session, handed to each test as if freshly migrated.

SQLite: the migrated file is copied (a file copy, no Alembic). PostgreSQL: the test database's
schema `public` is migrated once; each test then finds every table emptied with TRUNCATE ...
RESTART IDENTITY (ids start at 1 again), which needs neither a second database nor Alembic.
A test that changed the schema itself (migration tests drop it, campaign workers add
procrastinate's tables, tamper tests disable or drop triggers) is noticed by the schema's
fingerprint (its relations' oids, its triggers and whether they are enabled, the Alembic
revision and the template's stamp) and the schema is rebuilt and migrated again.

Each template carries a stamp of the session (SQLite `PRAGMA user_version`, a comment on the
PostgreSQL schema) so that a test can tell a template database from a fresh one
(tests/web/test_suite_fixtures.py)."""

from __future__ import annotations

import secrets
import shutil
import sqlite3
from dataclasses import dataclass, field
from pathlib import Path

from sqlalchemy import Connection, Engine, text
from sqlalchemy.exc import DBAPIError

from countersign.store.db import Database, make_engine

# The session's stamp: 1..2^31-1 fits SQLite's user_version (a signed 32-bit integer).
STAMP = secrets.randbelow(2**31 - 1) + 1
STAMP_COMMENT = f"countersign test template {STAMP}"
# A lock another connection holds (a test's stray server) fails the reset instead of hanging.
LOCK_TIMEOUT = "60s"


@dataclass(frozen=True)
class SqliteTemplate:
    path: Path

    @classmethod
    def migrate(cls, path: Path) -> SqliteTemplate:
        database = Database(f"sqlite:///{path}")
        database.migrate()
        database.engine.dispose()
        # Autocommit: PRAGMA user_version outside a transaction; closing the last connection
        # checkpoints the write-ahead log into the file, so the file alone is the database.
        connection = sqlite3.connect(path, isolation_level=None)
        try:
            connection.execute(f"PRAGMA user_version = {STAMP}")
            connection.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        finally:
            connection.close()
        return cls(path)

    def copy_to(self, target: Path) -> None:
        shutil.copyfile(self.path, target)
        for suffix in ("-wal", "-shm"):  # absent after the checkpoint; copied if ever present
            extra = self.path.with_name(self.path.name + suffix)
            if extra.exists():
                shutil.copyfile(extra, target.with_name(target.name + suffix))


def sqlite_stamp(path: Path) -> int:
    connection = sqlite3.connect(path)
    try:
        return int(connection.execute("PRAGMA user_version").fetchone()[0])
    finally:
        connection.close()


def postgres_stamp(connection: Connection) -> str | None:
    value = connection.execute(text("SELECT obj_description('public'::regnamespace)")).scalar()
    return None if value is None else str(value)


@dataclass
class PostgresTemplate:
    url: str
    engine: Engine = field(init=False)
    fingerprint: tuple[object, ...] | None = field(init=False, default=None)
    tables: list[str] = field(init=False, default_factory=list)
    rebuilds: int = field(init=False, default=0)

    def __post_init__(self) -> None:
        self.engine = make_engine(self.url)

    def close(self) -> None:
        self.engine.dispose()

    def reset(self) -> None:
        """The test database as migration left it: every table empty, ids from 1."""
        with self.engine.begin() as connection:
            connection.execute(text(f"SET LOCAL lock_timeout = '{LOCK_TIMEOUT}'"))
            if self.fingerprint is not None and _fingerprint(connection) == self.fingerprint:
                try:
                    with connection.begin_nested():
                        # The append-only tables refuse TRUNCATE by trigger (migration 0002):
                        # replica mode (a superuser's, as the test servers' postgres is) skips
                        # triggers for this transaction only.
                        connection.execute(text("SET LOCAL session_replication_role = replica"))
                        connection.execute(text(f"TRUNCATE {', '.join(self.tables)} "
                                                "RESTART IDENTITY CASCADE"))
                    return
                except DBAPIError:  # not a superuser: migrate afresh, as before templates
                    pass
        self.rebuild()

    def empty(self) -> None:
        """The schema dropped and made again, with no tables: a database never migrated."""
        with self.engine.begin() as connection:
            connection.execute(text(f"SET LOCAL lock_timeout = '{LOCK_TIMEOUT}'"))
            connection.execute(text("DROP SCHEMA public CASCADE"))
            connection.execute(text("CREATE SCHEMA public"))

    def rebuild(self) -> None:
        self.empty()
        database = Database(self.url)
        try:
            database.migrate()
        finally:
            database.engine.dispose()
        with self.engine.begin() as connection:
            connection.execute(text(f"COMMENT ON SCHEMA public IS '{STAMP_COMMENT}'"))
            self.tables = [f'public."{name}"' for name in connection.execute(text(
                "SELECT c.relname FROM pg_class c JOIN pg_namespace n ON n.oid = c.relnamespace "
                "WHERE n.nspname = 'public' AND c.relkind IN ('r', 'p') "
                "AND c.relname <> 'alembic_version' ORDER BY c.relname")).scalars()]
            self.fingerprint = _fingerprint(connection)
        self.rebuilds += 1


def _fingerprint(connection: Connection) -> tuple[object, ...]:
    relations = tuple(connection.execute(text(
        "SELECT c.oid::bigint, c.relname, c.relkind FROM pg_class c "
        "JOIN pg_namespace n ON n.oid = c.relnamespace WHERE n.nspname = 'public' "
        "ORDER BY c.oid")).all())
    routines = connection.execute(text(
        "SELECT count(*) FROM pg_proc p JOIN pg_namespace n ON n.oid = p.pronamespace "
        "WHERE n.nspname = 'public'")).scalar_one()
    # Tamper tests disable or drop the append-only triggers to play a database writer; a
    # template reset must not hand the next test a table that no longer refuses updates.
    triggers = tuple(connection.execute(text(
        "SELECT t.tgrelid::bigint, t.tgname, t.tgenabled FROM pg_trigger t "
        "JOIN pg_class c ON c.oid = t.tgrelid JOIN pg_namespace n ON n.oid = c.relnamespace "
        "WHERE n.nspname = 'public' AND NOT t.tgisinternal ORDER BY t.tgrelid, t.tgname")).all())
    try:
        with connection.begin_nested():
            revision = tuple(connection.execute(text(
                "SELECT version_num FROM alembic_version ORDER BY version_num")).scalars())
    except DBAPIError:
        revision = ()
    return relations, routines, triggers, revision, postgres_stamp(connection)
