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

Fair queuing (issue 15: one user's 76-second validation made every other user's edit wait 72 s):
each submitter (the signed-in user) has a queue of their own, and a free process takes the head
of the queue of the user who has the fewest validations running, the one served longest ago
first. A user runs at most `processes - 1` validations at once, so with two or more processes
one is always left for someone else's small edit, however many heavy jobs one user sends.
"""

from __future__ import annotations

import contextlib
import itertools
import multiprocessing
import os
import threading
from collections import deque
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from contextvars import ContextVar
from typing import TYPE_CHECKING, Any

from ..orders.model import Orders
from ..pool_lifetime import end_with

if TYPE_CHECKING:
    from ..verify.parts import PartKeys

NICENESS = 5  # below the web processes: reads first, validations in the gaps
CHECKS_MODULE = "countersign.verify.report"

# Who asks for the validation running in this context: routes set it (fair.py) before handing
# the work to a thread, which copies the context. Unset, work shares one anonymous queue.
SUBMITTER: ContextVar[str] = ContextVar("countersign_validation_submitter", default="")


# A validation process is replaced after this many validations. z3 and the solver caches keep
# memory they never give back (bench_rss: one process grew 109 -> 188 MB over 8 rounds of heavy
# validations), so fresh processes bound the pool's RSS; the forkserver has the checks
# preloaded, so a replacement costs a fork, not an import.
TASKS_PER_PROCESS = 20


def _lower_priority(owner_pid: int) -> None:
    end_with(owner_pid)
    with contextlib.suppress(OSError):  # not permitted: run at the web processes' priority
        os.nice(NICENESS)


def _validate(orders: Orders) -> tuple[int, dict[str, Any]]:
    from ..verify.report import validate

    return os.getpid(), validate(orders).to_json()


def _validate_parts(orders: Orders, known: dict[str, Any], keys: PartKeys, orders_digest: str
                    ) -> tuple[int, dict[str, Any], dict[str, Any]]:
    """The report, computing only the parts not handed over (and not held in this process
    from an earlier validation), and the parts it consists of, for the caller to keep."""
    from ..verify.parts import SHARED_PARTS
    from ..verify.report import validate

    SHARED_PARTS.update(known)
    report = validate(orders, parts=SHARED_PARTS, keys=keys, orders_digest=orders_digest)
    return os.getpid(), report.to_json(), SHARED_PARTS.items(keys)


class ValidationPool:
    def __init__(self, processes: int) -> None:
        if processes < 1:
            raise ValueError("a validation pool needs at least one process")
        self.processes = processes
        # Before anything starts the forkserver (the password hasher shares it), so that it
        # has the checks imported and a replacement process costs a fork, not an import.
        multiprocessing.get_context("forkserver").set_forkserver_preload([CHECKS_MODULE])
        self._lock = threading.Lock()
        self._executor: ProcessPoolExecutor | None = None
        self.last_pid: int | None = None  # the process that ran the last validation
        self.per_user = max(1, processes - 1)
        self._turns = threading.Condition()
        self._waiting: dict[str, deque[object]] = {}
        self._running: dict[str, int] = {}
        self._served: dict[str, int] = {}  # when each user was last given a process
        self._clock = itertools.count()
        self._busy = 0

    def running(self, submitter: str) -> int:
        """How many validations of this submitter are in a process now (tests poll it)."""
        with self._turns:
            return self._running.get(submitter, 0)

    def pending(self, submitter: str) -> int:
        """How many validations of this submitter are running or waiting for their turn."""
        with self._turns:
            return self._running.get(submitter, 0) + len(self._waiting.get(submitter, ()))

    def _next_ticket(self) -> object | None:
        """The ticket whose turn it is, if a process is free."""
        if self._busy >= self.processes:
            return None
        eligible = [u for u, q in self._waiting.items()
                    if q and self._running.get(u, 0) < self.per_user]
        if not eligible:
            return None
        user = min(eligible, key=lambda u: (self._running.get(u, 0), self._served.get(u, -1)))
        return self._waiting[user][0]

    @contextlib.contextmanager
    def _turn(self, submitter: str) -> Iterator[None]:
        ticket = object()
        with self._turns:
            self._waiting.setdefault(submitter, deque()).append(ticket)
            while self._next_ticket() is not ticket:
                self._turns.wait()
            queue = self._waiting[submitter]
            queue.popleft()
            if not queue:
                del self._waiting[submitter]
            self._busy += 1
            self._running[submitter] = self._running.get(submitter, 0) + 1
            self._served[submitter] = next(self._clock)
            # Another process may be free for another user's head ticket.
            self._turns.notify_all()
        try:
            yield
        finally:
            with self._turns:
                self._busy -= 1
                self._running[submitter] -= 1
                if not self._running[submitter]:
                    del self._running[submitter]
                self._turns.notify_all()

    def _current(self) -> ProcessPoolExecutor:
        with self._lock:
            if self._executor is None:
                context = multiprocessing.get_context("forkserver")
                self._executor = ProcessPoolExecutor(
                    self.processes, mp_context=context, initializer=_lower_priority,
                    initargs=(os.getpid(),), max_tasks_per_child=TASKS_PER_PROCESS)
            return self._executor

    def validate(self, orders: Orders, submitter: str | None = None) -> dict[str, Any]:
        """The report of `verify.validate(orders)`, computed in a pool process when it is
        the submitter's turn (by default SUBMITTER of the calling context). A pool broken by a
        dead process (killed, out of memory) is replaced once."""
        with self._turn(SUBMITTER.get() if submitter is None else submitter):
            report: dict[str, Any] = self._run(orders)
            return report

    def validate_parts(self, orders: Orders, known: dict[str, Any], keys: PartKeys,
                       orders_digest: str, submitter: str | None = None
                       ) -> tuple[dict[str, Any], dict[str, Any]]:
        """As validate, handing over the report parts already known (verify.parts): the
        process computes the others and returns the report with all its parts."""
        with self._turn(SUBMITTER.get() if submitter is None else submitter):
            report, parts = self._run(orders, known, keys, orders_digest)
            return report, parts

    def _run(self, orders: Orders, *handed: Any) -> Any:
        for attempt in (1, 2):
            executor = self._current()
            try:
                if handed:
                    pid, *result = executor.submit(_validate_parts, orders, *handed).result()
                else:
                    pid, report = executor.submit(_validate, orders).result()
                    result = [report]
            except BrokenProcessPool:
                with self._lock:
                    if self._executor is executor:
                        self._executor = None
                executor.shutdown(wait=False, cancel_futures=True)
                if attempt == 2:
                    raise
                continue
            self.last_pid = pid
            return result[0] if len(result) == 1 else tuple(result)
        raise AssertionError("unreachable")

    def shutdown(self) -> None:
        with self._lock:
            executor, self._executor = self._executor, None
        if executor is not None:
            executor.shutdown(wait=True, cancel_futures=True)
