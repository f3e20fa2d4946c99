"""Engines, sessions and schema migration (Alembic, upgraded to head on start)."""

from __future__ import annotations

import functools
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Engine, create_engine, event
from sqlalchemy.exc import TimeoutError as PoolTimeout
from sqlalchemy.orm import Session, sessionmaker

from .report_service import ReportService

if TYPE_CHECKING:
    from ..approvals.merkle import Tree
    from ..approvals.signer import LogSigner

MIGRATIONS = Path(__file__).resolve().parents[3] / "migrations"


class DatabaseTooNew(RuntimeError):
    """The database was migrated by a newer Countersign than this one."""


BEGIN_MODE = "countersign_begin"
_HOLDS_WRITE_LOCK = "countersign_holds_write_lock"


# Threads that run a server process's synchronous routes (anyio's default is 40). The CPU
# work is bounded by the cores and the interpreter lock; more threads only add switching.
REQUEST_THREADS = 24

# How long a SQLite writer waits for the write lock before the request fails with 503.
WRITE_LOCK_TIMEOUT_S = 30.0


def make_engine(url: str) -> Engine:
    if url.startswith("sqlite"):
        return _sqlite_engine(url)
    if url.startswith("postgresql://"):
        url = "postgresql+psycopg://" + url.removeprefix("postgresql://")
    # One connection per server thread (REQUEST_THREADS) stays open; a thread may briefly hold
    # a second (a short report-cache session beside its request's), taken from the overflow.
    # Without the steady pool, connections opened under a burst were closed again at once and
    # PostgreSQL forked a backend for each new one: most of its CPU under 50 clients. At most
    # 2 x REQUEST_THREADS connections per server process (README: max_connections).
    return create_engine(url, pool_size=REQUEST_THREADS, max_overflow=REQUEST_THREADS,
                         pool_timeout=10, pool_recycle=3600, pool_pre_ping=True)


def _sqlite_engine(url: str) -> Engine:
    # Up to two connections per worker thread (request session + report cache writer).
    engine = create_engine(url, connect_args={"check_same_thread": False, "timeout": 30},
                           pool_size=REQUEST_THREADS, max_overflow=REQUEST_THREADS,
                           pool_timeout=10)

    @event.listens_for(engine, "connect")
    def _sqlite_pragmas(dbapi_connection: Any, _record: Any) -> None:
        # SQLAlchemy emits BEGIN itself (_queue_writers), so the driver must not.
        dbapi_connection.isolation_level = None
        cursor = dbapi_connection.cursor()
        cursor.execute("PRAGMA journal_mode=WAL")
        cursor.execute("PRAGMA foreign_keys=ON")
        cursor.execute("PRAGMA busy_timeout=30000")
        cursor.close()

    _queue_writers(engine)
    return engine


def _queue_writers(engine: Engine) -> None:
    """SQLite has one writer at a time. Writers of this process queue on a lock of their
    own before asking SQLite: they are woken the moment the previous writer commits,
    instead of polling in SQLite's busy handler (which sleeps up to 100 ms between tries
    and lets late comers overtake). Writers of other processes still meet busy_timeout."""
    write_lock = threading.Lock()

    @event.listens_for(engine, "begin")
    def _sqlite_begin(connection: Any) -> None:
        # A writer takes the write lock when it begins (IMMEDIATE): a deferred transaction
        # that reads and then writes cannot upgrade once another writer committed, and
        # SQLite answers that with "database is locked" instead of waiting.
        mode = connection.get_execution_options().get(BEGIN_MODE, "DEFERRED")
        if mode == "IMMEDIATE":
            if not write_lock.acquire(timeout=WRITE_LOCK_TIMEOUT_S):
                raise PoolTimeout("another writer held the SQLite write lock too long")
            connection.info[_HOLDS_WRITE_LOCK] = True
        try:
            connection.exec_driver_sql(f"BEGIN {mode}")
        except BaseException:
            _release(connection.info)
            raise

    def _release(info: dict[str, Any]) -> None:
        if info.pop(_HOLDS_WRITE_LOCK, False):
            write_lock.release()

    # A session gives its connection back to the pool right after COMMIT or ROLLBACK: the
    # next writer may go then. (The "commit" event would fire before COMMIT is sent.)
    @event.listens_for(engine, "checkin")
    def _sqlite_checkin(_dbapi_connection: Any, record: Any) -> None:
        if record is not None:
            _release(record.info)

    @event.listens_for(engine, "invalidate")
    def _sqlite_invalidate(_dbapi_connection: Any, record: Any, _error: Any) -> None:
        if record is not None:
            _release(record.info)


def alembic_config(url: str) -> Config:
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS))
    config.set_main_option("sqlalchemy.url", url.replace("%", "%%"))
    return config


@functools.cache
def _revisions() -> tuple[frozenset[str], frozenset[str]]:
    """Every revision the migrations folder knows, and its heads. Read once per process: the
    folder ships with the code, and loading its scripts is most of a start at head."""
    script = ScriptDirectory.from_config(alembic_config(""))
    return (frozenset(rev.revision for rev in script.walk_revisions()),
            frozenset(script.get_heads()))


def upgrade_to_head(engine: Engine) -> None:
    """Bring the schema to this version's head; refuse a database from a newer version."""
    config = alembic_config(engine.url.render_as_string(hide_password=False))
    known, heads = _revisions()
    with engine.connect() as connection:
        current = MigrationContext.configure(connection).get_current_heads()
    unknown = [rev for rev in current if rev not in known]
    if unknown:
        raise DatabaseTooNew(
            f"the database is at schema revision {', '.join(unknown)}, which this version of "
            "Countersign does not know: it was upgraded by a newer version. Refusing to start."
        )
    if set(current) == heads:
        return  # at head already: Alembic would load every script again to do nothing
    with engine.begin() as connection:
        config.attributes["connection"] = connection
        command.upgrade(config, "head")


class LogTreeCache:
    """The committed log's Merkle tree (store/approvals/log.py), extended as the log grows.
    Owned by the Database object, so that two databases never share one."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.tree: Tree | None = None

    def clear(self) -> None:
        with self.lock:
            self.tree = None


class ReadSession(Session):
    """A read-only session: it never takes the write lock, and refuses to flush a change."""


class WriteSession(Session):
    """A session that writes: its transaction takes the write lock when it begins (SQLite's
    BEGIN IMMEDIATE)."""


def writes(session: Session) -> bool:
    """Whether the session may write (holds, or will take, the write lock): any session but a
    ReadSession (a plain Session, as some tools and tests open, writes)."""
    return not isinstance(session, ReadSession)


class Database:
    def __init__(self, url: str) -> None:
        self.url = url
        # Computes validation reports when none is stored (single flight, reuse, the pool).
        self.reports = ReportService()
        self.engine = make_engine(url)
        # The log signer (approvals/signer.py) that receipts each appended entry; set by
        # whoever holds the log key (the server, the CLI's demo seeding).
        self.log_signer: LogSigner | None = None
        self.log_tree_cache = LogTreeCache()
        self.sessions = sessionmaker(self.engine, class_=ReadSession, expire_on_commit=False)
        self.write_sessions = sessionmaker(
            self.engine.execution_options(**{BEGIN_MODE: "IMMEDIATE"}), class_=WriteSession,
            expire_on_commit=False
        )

    def migrate(self) -> None:
        upgrade_to_head(self.engine)

    @contextmanager
    def open(self, write: bool = True) -> Iterator[Session]:
        """A session whose transaction begins at its first query (a writer's BEGIN IMMEDIATE
        on SQLite: the write lock) and that may be committed early; committed on success if
        still open, rolled back on error."""
        factory = self.write_sessions if write else self.sessions
        # "may_end": what it has begun may be ended early (login_throttle.check_password).
        with factory(info={"database": self, "may_end": True}) as session:
            if not write:
                event.listen(session, "before_flush", _refuse_writes)
            try:
                yield session
                session.commit()
            except BaseException:
                session.rollback()
                raise

    @contextmanager
    def session(self, write: bool = True) -> Iterator[Session]:
        """A transaction, committed on success. Pass write=False for read-only work: on SQLite
        readers then never wait for the write lock."""
        factory = self.write_sessions if write else self.sessions
        with factory(info={"database": self}) as session, session.begin():
            if not write:
                event.listen(session, "before_flush", _refuse_writes)
            yield session


def _refuse_writes(session: Session, _context: Any, _instances: Any) -> None:
    if session.new or session.dirty or session.deleted:
        raise RuntimeError("a read-only session tried to write; open a write session instead")


def database_of(session: Session) -> Database:
    """The database that opened the session, to open a short session of its own beside it."""
    database: Database = session.info["database"]
    return database


# The store reaches an app service through a session at one place only, below what a route
# calls: the log's Merkle tree cache (approvals/log.py). The log signer is an argument
# (`record(..., signer=)`), given by routes from AppServices (services/app.py) and by the CLI
# from the database it opened; tests/codebase/test_no_info_services.py holds both rules.
def log_trees_of(session: Session) -> LogTreeCache | None:
    """The cached Merkle tree of the log of the session's database (None: no database)."""
    database: Database | None = session.info.get("database")
    return database.log_tree_cache if database is not None else None


@contextmanager
def writable(session: Session) -> Iterator[Session]:
    """A session to write through: this one (in a savepoint) when it may write, else a short
    write transaction of its own. Never a second writer beside a writing session: on SQLite
    that would wait for a lock its own thread holds."""
    if writes(session):
        with session.begin_nested():
            yield session
    else:
        with database_of(session).session() as writer:
            yield writer
