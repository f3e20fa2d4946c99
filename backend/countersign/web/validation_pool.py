"""Validation in processes of its own, beside the web server's.

A validation is tens of milliseconds of pure Python (the MEO check, z3, the rules). Run in a
thread of the web process it holds the interpreter lock in slices of 5 ms, and every read
served meanwhile by that process waits for the lock again after each database call: under 50
clients, reads queued behind the validations of other clients' edits (issue 5's read p99).
In a process of its own it competes for a core under the operating system's scheduler
instead, at a lower priority (nice), so that short reads go first and a validation still
finishes well inside its one-second target.

Workers are forked from a forkserver that imported the checks once, so starting one is cheap
and every app in a process (the test suite's many) shares that one import.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import threading
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from ..orders.model import Orders

NICENESS = 5  # below the web processes: reads first, validations in the gaps
CHECKS_MODULE = "countersign.rehearse.checks"


def _lower_priority() -> None:
    with contextlib.suppress(OSError):  # not permitted: run at the web processes' priority
        os.nice(NICENESS)


def _validate(orders: Orders) -> tuple[int, dict[str, Any]]:
    from ..rehearse.checks import validate_with_rules

    return os.getpid(), validate_with_rules(orders).to_json()


class ValidationPool:
    def __init__(self, processes: int) -> None:
        if processes < 1:
            raise ValueError("a validation pool needs at least one process")
        self.processes = processes
        self._lock = threading.Lock()
        self._executor: ProcessPoolExecutor | None = None
        self.last_pid: int | None = None  # the process that ran the last validation

    def _current(self) -> ProcessPoolExecutor:
        with self._lock:
            if self._executor is None:
                context = multiprocessing.get_context("forkserver")
                context.set_forkserver_preload([CHECKS_MODULE])
                self._executor = ProcessPoolExecutor(
                    self.processes, mp_context=context, initializer=_lower_priority)
            return self._executor

    def validate(self, orders: Orders) -> dict[str, Any]:
        """The report of `validate_with_rules(orders)`, computed in a pool process. A pool
        broken by a dead process (killed, out of memory) is replaced once."""
        for attempt in (1, 2):
            executor = self._current()
            try:
                pid, report = executor.submit(_validate, orders).result()
            except BrokenProcessPool:
                with self._lock:
                    if self._executor is executor:
                        self._executor = None
                executor.shutdown(wait=False, cancel_futures=True)
                if attempt == 2:
                    raise
                continue
            self.last_pid = pid
            return report
        raise AssertionError("unreachable")

    def shutdown(self) -> None:
        with self._lock:
            executor, self._executor = self._executor, None
        if executor is not None:
            executor.shutdown(wait=True, cancel_futures=True)
