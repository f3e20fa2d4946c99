"""Whether a request holds SQLite's one write lock while it does some long piece of work, and
which sessions a request opens for writing (record_opens).

A route that validates, checks, hashes or builds a simulation inside its write transaction
makes every other user's writes wait for it. The tests wrap that piece of work: each call first
tries to take the write lock from a connection of its own, and records whether it could."""

from __future__ import annotations

import sqlite3
from contextlib import AbstractContextManager
from typing import Any

import pytest
from sqlalchemy.orm import Session

from .conftest import World


def write_lock_free(path: str) -> bool:
    """Whether another connection could begin a write on the database file right now."""
    other = sqlite3.connect(path, timeout=0, isolation_level=None)
    try:
        other.execute("BEGIN IMMEDIATE")
        other.execute("ROLLBACK")
        return True
    except sqlite3.OperationalError:
        return False
    finally:
        other.close()


def probe_write_lock(world: World, monkeypatch: pytest.MonkeyPatch, owner: object,
                     name: str) -> list[bool]:
    """Wrap `owner.name` so that each call records whether the write lock was free as it
    began; returns the list the calls append to. Skips the test off SQLite."""
    if world.database.engine.dialect.name != "sqlite":
        pytest.skip("the single write lock is SQLite's")
    path = world.database.engine.url.database
    assert path
    free_at_calls: list[bool] = []
    original = getattr(owner, name)

    def probe(*args: Any, **kwargs: Any) -> Any:
        free_at_calls.append(write_lock_free(path))
        return original(*args, **kwargs)

    monkeypatch.setattr(owner, name, probe)
    return free_at_calls


def record_opens(world: World, monkeypatch: pytest.MonkeyPatch) -> list[bool]:
    """Each request session's `write` flag, in the order the sessions open."""
    opened: list[bool] = []
    real = world.database.open

    def recording(write: bool = True) -> AbstractContextManager[Session]:
        opened.append(write)
        return real(write=write)

    monkeypatch.setattr(world.database, "open", recording)
    return opened
