"""Argon2 with bounded concurrency.

An Argon2 hash is tens of milliseconds of a core and 64 MiB of memory. Run in the server's
worker threads it releases the interpreter lock, so 96 anonymous logins at once ran 24 hashes
side by side, took every core from the event loop and pushed /api/health to 17.8 s (issue
15). Hashes here take a slot first: at most one fewer than the cores (and at least one), so
the rest of the server keeps a core; logins beyond that wait in their threads, off the event
loop.
"""

from __future__ import annotations

import os
import threading
from typing import Any, Literal

from argon2 import PasswordHasher

HASH_SLOTS = max(1, (os.cpu_count() or 1) - 1)


class BoundedHasher(PasswordHasher):
    """argon2-cffi's PasswordHasher whose hash and verify take one of `slots` at a time."""

    def __init__(self, *args: Any, slots: int = HASH_SLOTS, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.slots = threading.BoundedSemaphore(slots)

    def hash(self, password: str | bytes, *, salt: bytes | None = None) -> str:
        with self.slots:
            return super().hash(password, salt=salt)

    def verify(self, hash: str | bytes, password: str | bytes) -> Literal[True]:
        with self.slots:
            return super().verify(hash, password)
