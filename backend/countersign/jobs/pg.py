"""Campaign jobs on PostgreSQL with procrastinate: the server and the CLI defer one job per
chunk; `countersign campaign worker` processes run them.

A worker killed with SIGKILL stops sending heartbeats; every live worker looks for jobs of
stalled workers (no heartbeat for `stalled_after_s`) and puts them back in the queue, where
the retry skips what was already stored. procrastinate's own tables live beside ours; its
schema is applied once, on first use, under an advisory lock.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

import procrastinate
import psycopg

from ..store import campaigns as store
from ..store.db import Database
from .tasks import run_chunk

log = logging.getLogger("countersign.campaigns")
QUEUE = "campaigns"
TASK = "countersign.campaign_chunk"
SCHEMA_LOCK = 0x43534348  # pg_advisory_lock key while applying procrastinate's schema
# A job that raises (a lost database connection, say) is tried again a few times.
ATTEMPTS = 5
RETRY = procrastinate.RetryStrategy(max_attempts=ATTEMPTS - 1, wait=2)

_worker_database: Database | None = None


def conninfo(database_url: str) -> str:
    """libpq's form of the SQLAlchemy URL (procrastinate talks to psycopg directly)."""
    for prefix in ("postgresql+psycopg://", "postgres://"):
        if database_url.startswith(prefix):
            return "postgresql://" + database_url.removeprefix(prefix)
    return database_url


def campaign_chunk(context: procrastinate.JobContext, campaign_id: str, start: int,
                   stop: int) -> int:
    database = _worker_database
    if database is None:
        raise RuntimeError("campaign jobs run in `countersign campaign worker`")
    try:
        return run_chunk(database, campaign_id, start, stop)
    except Exception as exc:
        job = context.job
        if job is not None and job.attempts + 1 >= ATTEMPTS:
            with database.session() as db:
                store.fail(db, campaign_id, f"a job failed {ATTEMPTS} times: "
                           f"{type(exc).__name__}: {exc}")
        raise


def make_app(database_url: str) -> procrastinate.App:
    app = procrastinate.App(connector=procrastinate.PsycopgConnector(
        conninfo=conninfo(database_url)))
    app.task(name=TASK, queue=QUEUE, retry=RETRY, pass_context=True)(campaign_chunk)
    return app


def ensure_schema(database_url: str) -> None:
    """Apply procrastinate's schema if this database lacks it."""
    with psycopg.connect(conninfo(database_url), autocommit=True) as connection:
        connection.execute("SELECT pg_advisory_lock(%s)", (SCHEMA_LOCK,))
        try:
            present = connection.execute(
                "SELECT to_regclass('procrastinate_jobs') IS NOT NULL").fetchone()
            if present and present[0]:
                return
            app = make_app(database_url)
            with app.open():
                app.schema_manager.apply_schema()
        finally:
            connection.execute("SELECT pg_advisory_unlock(%s)", (SCHEMA_LOCK,))


class ProcrastinateRunner:
    """Defers jobs for the workers (it runs none itself)."""

    def __init__(self, database: Database) -> None:
        ensure_schema(database.url)
        self.database = database
        self.app = make_app(database.url)
        self.app.open()

    def enqueue(self, campaign_id: str, chunks: list[tuple[int, int]]) -> None:
        # Workers take the highest priority first: each job's is minus the jobs its owner has
        # ahead of it, so owners' queues interleave and another person's small campaign is
        # not left behind one person's 10,000 simulations.
        with self.database.session(write=False) as db:
            ahead = store.owner_backlog(db, campaign_id)
        task = self.app.tasks[TASK]
        size = max(1, chunks[0][1] - chunks[0][0]) if chunks else 1
        for start, stop in chunks:
            behind = min((ahead + start) // size, 2**31 - 1)
            task.configure(priority=-behind).defer(campaign_id=campaign_id, start=start,
                                                   stop=stop)

    def close(self) -> None:
        with contextlib.suppress(Exception):
            self.app.close()


async def _requeue_stalled(app: procrastinate.App, *, every_s: float,
                           stalled_after_s: float) -> None:
    while True:
        await asyncio.sleep(every_s)
        try:
            stalled = await app.job_manager.get_stalled_jobs(
                queue=QUEUE, seconds_since_heartbeat=stalled_after_s)
            for job in stalled:
                log.warning("campaign job %s of a stalled worker goes back in the queue",
                            job.id)
                await app.job_manager.retry_job(job)
        except Exception as exc:  # a lost connection: try again next round
            log.warning("could not look for stalled campaign jobs: %r", exc)


def run_worker(database_url: str, *, concurrency: int = 1, name: str | None = None,
               heartbeat_s: float = 5.0, stalled_after_s: float = 30.0,
               wait: bool = True) -> None:
    """Run campaign jobs until stopped (SIGINT/SIGTERM); with wait=False, until the queue is
    empty."""
    global _worker_database
    ensure_schema(database_url)
    _worker_database = Database(database_url)
    app = make_app(database_url)

    async def main() -> None:
        async with app.open_async():
            reaper = asyncio.create_task(_requeue_stalled(
                app, every_s=max(1.0, heartbeat_s), stalled_after_s=stalled_after_s))
            try:
                options: dict[str, Any] = {
                    "queues": [QUEUE], "concurrency": concurrency, "name": name,
                    "wait": wait, "update_heartbeat_interval": heartbeat_s,
                    "stalled_worker_timeout": stalled_after_s,
                }
                await app.run_worker_async(**options)
            finally:
                reaper.cancel()

    asyncio.run(main())
