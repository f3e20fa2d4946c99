"""Campaign jobs: one task function, run by procrastinate workers on PostgreSQL
(`pg.py`, `countersign campaign worker`) or by a small in-process runner on SQLite
(`inprocess.py`). Both call `tasks.run_chunk`, which is idempotent per (campaign, index)."""

from __future__ import annotations

from typing import Protocol

from ..store.db import Database


class CampaignRunner(Protocol):
    def enqueue(self, campaign_id: str, chunks: list[tuple[int, int]]) -> None: ...

    def close(self) -> None: ...


def is_postgres(database: Database) -> bool:
    return database.engine.dialect.name == "postgresql"


def runner_for(database: Database, *, workers: int = 1) -> CampaignRunner:
    """procrastinate on PostgreSQL (jobs wait for `countersign campaign worker`), the
    in-process runner on SQLite."""
    if is_postgres(database):
        from .pg import ProcrastinateRunner

        return ProcrastinateRunner(database)
    from .inprocess import InProcessRunner

    return InProcessRunner(database, workers=workers)
