"""What each pytest-xdist worker keeps to itself when the suite runs in parallel (`-n 2`,
./scripts/test), and how tests are handed out to the workers.

- PostgreSQL: every worker gets a database of its own, named after the suite's
  (COUNTERSIGN_TEST_POSTGRES_URL) with the worker's id appended (cs_a -> cs_a_gw0), created
  when missing. The variable itself is rewritten in the worker before any test module reads
  it, so fixtures, test modules and the processes tests start (campaign workers, servers)
  all see the worker's database. Two workers on one database would truncate each other's
  tables mid-test.
- Temporary folders (SQLite templates, data dirs, e2e servers' folders) come from
  tmp_path_factory, which xdist already gives a base folder per worker; the ports of the
  servers tests start come from tests/ports.py, which no two workers (nor sessions) share.
- ./scripts/test hands out whole modules (`--dist loadfile`), so a module- or class-scoped
  set-up (a MOOS-IvP flight of minutes, a seeded fuzz app) runs once, not once on each
  worker. (`--dist loadgroup` with xdist_group marks would let the other modules' tests
  spread, but with pytest 9.2 and pytest-xdist 3.8 it groups nothing: xdist renames
  `item._nodeid`, which pytest no longer reads.)
- Under xdist the long modules are handed out first, so that neither worker is left with a
  several-minute module at the end while the other idles: the workers collect them first
  (heavy_first) and ./scripts/test's --no-loadscope-reorder keeps that order (xdist's default
  hands out the modules with the most tests first)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from sqlalchemy import create_engine, text
from sqlalchemy.engine import make_url

POSTGRES_VARIABLE = "COUNTERSIGN_TEST_POSTGRES_URL"
TESTS = Path(__file__).resolve().parent
# The longest modules and folders, longest first (`--durations=250` of full runs: ci10.log, and
# 2026-12-05's at load 10, where the server-starting modules weigh more): with the long ones
# handed out first and the many short modules after them, the workers end within a short
# module of each other (greedy, longest first). A folder's entry takes the modules not named.
HEAVY_FIRST = (
    "web/test_fuzz.py",
    "export/test_moos_team.py",
    "e2e/test_editor_build_exemplar.py",
    "e2e/test_no_foreign_script.py",
    "campaigns/test_campaign_kill.py",
    "export/test_moos_helm.py",
    "web/test_password_throttle.py",
    "e2e/test_editor_panels.py",
    "web/test_approval_process.py",
    "rehearse/test_budget_bound.py",
    "e2e/test_editor_canvas.py",
    "e2e/test_rehearsal_screen.py",
    "e2e/test_rehearsal_refined.py",
    "e2e/test_roles.py",
    "e2e/test_rehearsal_team.py",
    "e2e/",
    "web/test_accounts.py",
    "rehearse/test_refined_rehearsal.py",
    "web/test_fair.py",
    "web/test_fair_across_workers.py",
    "web/test_campaigns.py",
    "web/test_account_hygiene.py",
    "web/test_decision_races.py",
    "campaigns/",
)


def worker_id() -> str | None:
    """The xdist worker's id ("gw0", "gw1", ...), None in a run without workers."""
    return os.environ.get("PYTEST_XDIST_WORKER")


def worker_database_url(url: str, worker: str) -> str:
    """The worker's own database on the suite's PostgreSQL server: the suite's database name
    with the worker's id appended."""
    parsed = make_url(url)
    if not parsed.database:
        raise ValueError(f"{POSTGRES_VARIABLE} names no database: {parsed!r}")
    return parsed.set(database=f"{parsed.database}_{worker}").render_as_string(
        hide_password=False)


def create_database(url: str, via: str) -> None:
    """CREATE DATABASE for `url`'s database unless it exists, connected to `via` (the
    suite's database, which exists)."""
    target = make_url(url)
    engine = create_engine(make_url(via).set(drivername="postgresql+psycopg"),
                           isolation_level="AUTOCOMMIT")
    try:
        with engine.connect() as connection:
            found = connection.execute(text("SELECT 1 FROM pg_database WHERE datname = :name"),
                                       {"name": target.database}).first()
            if found is None:
                quoted = str(target.database).replace('"', '""')
                connection.execute(text(f'CREATE DATABASE "{quoted}"'))
    finally:
        engine.dispose()


def separate_postgres() -> None:
    """Point this worker's COUNTERSIGN_TEST_POSTGRES_URL at a database of its own."""
    url, worker = os.environ.get(POSTGRES_VARIABLE), worker_id()
    if not url or not worker:
        return
    own = worker_database_url(url, worker)
    create_database(own, via=url)
    os.environ[POSTGRES_VARIABLE] = own


def _where(item: pytest.Item) -> str:
    try:
        return Path(item.path).resolve().relative_to(TESTS).as_posix()
    except ValueError:
        return item.nodeid.split("::", 1)[0]


def _heaviness(item: pytest.Item) -> int:
    where = _where(item)
    return next((rank for rank, heavy in enumerate(HEAVY_FIRST) if where.startswith(heavy)),
                len(HEAVY_FIRST))


def heavy_first(items: list[pytest.Item]) -> None:
    """Under xdist only: the long modules first (a stable sort: each keeps its order)."""
    if worker_id() is not None:
        items.sort(key=_heaviness)
