"""The cyclic garbage collector paused for the length of a logic check.

A cold check of a large mission builds about a hundred long-lived objects per goal (items with
their lazy phrases, memo entries, results), none of them garbage; every full collection walks
them all again, and at 10,000 goals the collections took a third of the check's CPU. Reference
counting still frees everything that is not in a cycle; cycles made meanwhile wait for the
next collection after the check.

Overlapping checks (threads of one process) share one count: the collector is enabled again
when the last of them ends, and only if it was enabled when the first began.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Iterator
from contextlib import contextmanager

_lock = threading.Lock()
_active = 0
_was_enabled = False


@contextmanager
def collector_paused() -> Iterator[None]:
    global _active, _was_enabled
    with _lock:
        if _active == 0:
            _was_enabled = gc.isenabled()
            gc.disable()
        _active += 1
    try:
        yield
    finally:
        with _lock:
            _active -= 1
            if _active == 0 and _was_enabled:
                gc.enable()
