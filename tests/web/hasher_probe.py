"""A look inside the password hasher's process pool, for tests only: which process hashes, and
at which niceness (store/hashing.py's BoundedHasher). Kept apart from the test modules so that
the forkserver's worker imports only this when it runs `_pid_and_niceness`."""

from __future__ import annotations

import os

from countersign.store.hashing import BoundedHasher


def _pid_and_niceness() -> tuple[int, int]:
    return os.getpid(), os.nice(0)


def probe(hasher: BoundedHasher) -> tuple[int, int] | None:
    """The pid and niceness of a hashing process, None when hashes run in threads."""
    with hasher._lock:
        executor, started = hasher._executor, hasher._started
    if executor is None or started is None:
        return None
    started.result()
    return executor.submit(_pid_and_niceness).result()
