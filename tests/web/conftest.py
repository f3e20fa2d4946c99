"""API fixtures: a real database (SQLite always; PostgreSQL when COUNTERSIGN_TEST_POSTGRES_URL
is set, as .ci/run does), users of every role, signed-in clients.

A test that uses the `world` starts from a database migrated once per session (Alembic per
test was most of a short test's cost): on SQLite a copy of a migrated template file, on
PostgreSQL the one migrated schema with every table emptied (tests/db_template.py).
The app still upgrades to head on start and finds head applied. A test that uses
`database_url` without the world gets an empty database, as before, to migrate as it likes."""

from __future__ import annotations

import functools
import os
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import pytest
import uvicorn
from fastapi import FastAPI
from fastapi.testclient import TestClient
from sqlalchemy import text

from countersign.orders.examples import load_example
from countersign.settings import Settings
from countersign.store import accounts, password_policy
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.store.hashing import BoundedHasher
from countersign.store.missions import create_mission
from countersign.web.app import create_app

from ..cheap_hashing import PRODUCTION_HASHER
from ..db_template import PostgresTemplate, SqliteTemplate
from ..ports import free_port

ROLES = ("operator", "supervisor", "auditor", "admin")
PASSWORD = "correct horse battery staple"
POSTGRES_URL = os.environ.get("COUNTERSIGN_TEST_POSTGRES_URL")


OPEN_TRANSACTIONS = text(
    "SELECT pid, application_name, now() - xact_start, left(query, 300) FROM pg_stat_activity "
    "WHERE datname = current_database() AND pid <> pg_backend_pid() "
    "AND state LIKE 'idle in transaction%'")


def watched(node: pytest.Item) -> bool:
    """Whether no_transaction_left_open looks after this test: one on PostgreSQL."""
    callspec = getattr(node, "callspec", None)
    return bool(POSTGRES_URL) and callspec is not None and \
        callspec.params.get("database_url") == "postgresql"


@pytest.fixture(autouse=True)
def no_transaction_left_open(request: pytest.FixtureRequest) -> Iterator[None]:
    """On PostgreSQL, a test that leaves a connection idle in a transaction fails itself and
    the connection is ended: otherwise its locks make a later test's reset of the worker's
    database wait (DROP SCHEMA, TRUNCATE) and that unrelated test fails instead."""
    if not watched(request.node):
        yield
        return
    # The template's engine: a connection of the suite's own to the worker's database.
    watch: PostgresTemplate = request.getfixturevalue("postgres_template")
    yield
    with watch.engine.begin() as connection:
        left = connection.execute(OPEN_TRANSACTIONS).all()
        for row in left:
            connection.execute(text("SELECT pg_terminate_backend(:pid)"), {"pid": row[0]})
    if left:
        pytest.fail("transactions left open (pid, application, age, last query): "
                    + "; ".join(repr(tuple(row)) for row in left), pytrace=False)


# Fixtures whose tests start from the migrated template rather than an empty database.
MIGRATED_FOR = ("world",)


@pytest.fixture(scope="session")
def sqlite_template(tmp_path_factory: pytest.TempPathFactory) -> SqliteTemplate:
    return SqliteTemplate.migrate(tmp_path_factory.mktemp("template") / "countersign.db")


@pytest.fixture(scope="session")
def postgres_template() -> Iterator[PostgresTemplate]:
    assert POSTGRES_URL
    template = PostgresTemplate(POSTGRES_URL)
    yield template
    template.close()


@pytest.fixture(params=["sqlite", "postgresql"])
def database_url(request: pytest.FixtureRequest, tmp_path: Path) -> str:
    migrated = any(name in request.fixturenames for name in MIGRATED_FOR)
    if request.param == "sqlite":
        path = tmp_path / "countersign.db"
        if migrated:
            request.getfixturevalue("sqlite_template").copy_to(path)
        return f"sqlite:///{path}"
    if not POSTGRES_URL:
        pytest.skip("PostgreSQL tests need COUNTERSIGN_TEST_POSTGRES_URL (.ci/run sets it)")
    template: PostgresTemplate = request.getfixturevalue("postgres_template")
    if migrated:
        template.reset()
    else:
        template.empty()
    return POSTGRES_URL


@dataclass
class World:
    app: FastAPI
    database: Database
    tokens: dict[str, str]
    usernames: dict[str, str]

    def client(self, role: str | None = None) -> TestClient:
        client = TestClient(self.app, raise_server_exceptions=False)
        if role is not None:
            client.headers["Authorization"] = f"Bearer {self.tokens[role]}"
        return client

    def browser(self, role: str) -> tuple[TestClient, str]:
        """A client signed in with a cookie session, and its CSRF token."""
        client = TestClient(self.app, raise_server_exceptions=False)
        response = client.post("/api/auth/login",
                               json={"username": self.usernames[role], "password": PASSWORD})
        assert response.status_code == 200, response.text
        return client, response.json()["csrf_token"]


# Every world seeds the same password for the same usernames: the policy's verdict (zxcvbn,
# milliseconds a user) is the same pure function's, remembered; and a test on production's
# hasher (production_hashing) gets its seeded users' production hashes made once a session
# (one per user, each with its own salt) instead of four 64 MiB hashes per world. The tests
# check passwords against them as before: only the seeding is spared.
_seeded_password_problem = functools.cache(password_policy.password_problem)
_SEEDED_PRODUCTION_HASHES: dict[int, str] = {}


class _SeedingHasher:
    """Stands in for production's hasher while a world is seeded: the n-th seeded user's hash
    of PASSWORD, made by that hasher the first time."""

    def __init__(self, real: BoundedHasher) -> None:
        self.real, self.made = real, 0

    def hash(self, password: str, **kwargs: object) -> str:
        assert password == PASSWORD and not kwargs, "only the world's seeding is stood in for"
        index, self.made = self.made, self.made + 1
        if index not in _SEEDED_PRODUCTION_HASHES:
            _SEEDED_PRODUCTION_HASHES[index] = self.real.hash(password)
        return _SEEDED_PRODUCTION_HASHES[index]


@contextmanager
def _seeding() -> Iterator[None]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(accounts, "password_problem", _seeded_password_problem)
        if accounts.HASHER is PRODUCTION_HASHER:
            patch.setattr(accounts, "HASHER", _SeedingHasher(PRODUCTION_HASHER))
        yield


def seed_users(database: Database) -> tuple[dict[str, str], dict[str, str]]:
    """One user per role (their API tokens and usernames) and the operator's example mission."""
    tokens: dict[str, str] = {}
    usernames: dict[str, str] = {}
    with _seeding(), database.session() as db:
        for role in ROLES:
            user = create_user(db, username=f"{role}1", role=role, password=PASSWORD,
                               signer=database.log_signer)
            usernames[role] = user.username
            tokens[role] = create_token(db, user=user, name="tests", signer=database.log_signer)[1]
            if role == "operator":
                create_mission(db, orders=load_example("search-and-sample"), author=user,
                               signer=database.log_signer)
    return tokens, usernames


@pytest.fixture
def world(database_url: str, tmp_path: Path) -> Iterator[World]:
    database = Database(database_url)
    app = create_app(Settings(data_dir=tmp_path, database_url=database_url), database)
    tokens, usernames = seed_users(database)
    # viser's GUI controls in the viewer (the CLI's layout): the proxy and gate tests click
    # them; the app itself keeps them on the page (tests/e2e/test_rehearsal_pace.py).
    app.state.rehearsals.viewer_controls = True
    yield World(app, database, tokens, usernames)
    app.state.rehearsals.shutdown()  # rehearsals a test started (their viser servers)
    database.engine.dispose()


def count_rows(database: Database, sql: str) -> int:
    with database.engine.connect() as connection:
        return int(connection.execute(text(sql)).scalar_one())


@pytest.fixture
def server(world: World) -> Iterator[str]:
    """The world's app served by a real uvicorn on a free loopback port, for clients that need
    HTTP (the command line, concurrent raw requests)."""
    port = free_port()
    instance = uvicorn.Server(uvicorn.Config(world.app, host="127.0.0.1", port=port,
                                             log_level="warning"))
    thread = threading.Thread(target=instance.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 120
    while not instance.started:
        assert time.monotonic() < deadline, "server did not start"
        time.sleep(0.05)
    yield f"http://127.0.0.1:{port}"
    instance.should_exit = True
    thread.join(timeout=30)
