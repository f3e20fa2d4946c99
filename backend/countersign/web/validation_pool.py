"""Validation in processes of its own, beside the web server's.

A validation is tens of milliseconds of pure Python (the MEO check, z3, the rules). Run in a
thread of the web process it holds the interpreter lock in slices of 5 ms, and every read
served meanwhile by that process waits for the lock again after each database call: under 50
clients, reads queued behind the validations of other clients' edits (the read p99).
In a process of its own it competes for a core under the operating system's scheduler
instead, at a lower priority (nice), so that short reads go first and a validation still
finishes well inside its one-second target.

Workers are forked from a forkserver that imported the checks once, so starting one is cheap
and every app in a process (the test suite's many) shares that one import.

Warm and keeping their caches: the processes start with the pool (the app's start) and each
validates a small example at once, so the first real validation finds z3 loaded and every
check's code run; each process keeps its caches (report parts, solver results) from job to job,
and a mission's validations go to the process that validated it last when it is free, where an
edit finds the results of the goals it left alone. A process is replaced only when its
resident memory passes a limit (z3 and the caches keep what they allocate), not after a count
of jobs, which emptied the caches of a busy server every few edits.

Fair queuing (one user's 76-second validation made every other user's edit wait 72 s):
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
import resource
import threading
from collections import deque
from collections.abc import Iterator
from concurrent.futures import Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextvars import ContextVar
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from cachetools import LRUCache

from ..orders.model import Orders
from ..pool_lifetime import end_with

if TYPE_CHECKING:
    from ..verify.parts import PartKeys

NICENESS = 5  # below the web processes: reads first, validations in the gaps
CHECKS_MODULE = "countersign.verify.every_check"  # the checks and what they load on demand
WARM_EXAMPLE = "search-and-sample"
# How long the app's start waits for its validation processes to warm up.
WARM_WAIT_S = 60.0

# Who asks for the validation running in this context: routes set it (fair.py) before handing
# the work to a thread, which copies the context. Unset, work shares one anonymous queue.
SUBMITTER: ContextVar[str] = ContextVar("countersign_validation_submitter", default="")


# A validation process whose resident memory passed this after a job is replaced. z3 and the
# solver caches keep memory they never give back (bench_rss: one process grew 109 -> 188 MB over
# 8 rounds of heavy validations), so fresh processes bound the pool's RSS; the forkserver has
# the checks preloaded, so a replacement costs a fork and a warm-up, not an import.
MAX_PROCESS_RSS = 768 * 2**20
# Missions whose last process is remembered (a mission id each).
HOMES_KEPT = 4096


def _lower_priority(owner_pid: int) -> None:
    end_with(owner_pid)
    with contextlib.suppress(OSError):  # not permitted: run at the web processes' priority
        os.nice(NICENESS)


def _rss() -> int:
    """This process's resident memory in bytes (its peak where /proc is not there)."""
    try:
        with open("/proc/self/statm", "rb") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _warm() -> int:
    """Run every check once on a small example, with every check's code loaded (the
    forkserver's preload, or here): the first real job then finds z3 and the checks' lazily
    imported code imported. The process id."""
    from ..orders.examples import load_example
    from ..verify import every_check  # noqa: F401
    from ..verify.logic import LogicCache
    from ..verify.parts import PartsCache
    from ..verify.report import validate

    # Caches of its own: the example's parts and results would only take the real jobs' room.
    validate(load_example(WARM_EXAMPLE), logic_cache=LogicCache(), parts=PartsCache())
    return os.getpid()


def _validate(orders: Orders) -> tuple[int, int, dict[str, Any]]:
    from ..verify.report import validate

    report = validate(orders).to_json()
    return os.getpid(), _rss(), report


def _validate_parts(orders: Orders, known: dict[str, Any], keys: PartKeys, orders_digest: str
                    ) -> tuple[int, int, dict[str, Any], dict[str, Any]]:
    """The report, computing only the parts not handed over (and not held in this process
    from an earlier validation), and its parts the caller did not hand over, for it to keep
    (sending back what it has would only cost pickling a thousand findings twice)."""
    from ..verify.parts import SHARED_PARTS
    from ..verify.report import validate

    SHARED_PARTS.update(known)
    report = validate(orders, parts=SHARED_PARTS, keys=keys, orders_digest=orders_digest)
    news = {k: v for k, v in SHARED_PARTS.items(keys).items() if k not in known}
    return os.getpid(), _rss(), report.to_json(), news


@dataclass
class _Lane:
    """One validation process (an executor of one worker, so that a job can be sent to the
    process that holds its mission's caches)."""

    executor: ProcessPoolExecutor
    warm: Future[int]
    busy: bool = False
    used: int = 0  # when it last took a job (the pool's clock)


class ValidationPool:
    def __init__(self, processes: int, *, max_rss: int | None = None) -> None:
        if processes < 1:
            raise ValueError("a validation pool needs at least one process")
        self.processes = processes
        self.max_rss = MAX_PROCESS_RSS if max_rss is None else max_rss
        # Before anything starts the forkserver (the password hasher shares it), so that it
        # has the checks imported and a replacement process costs a fork, not an import.
        multiprocessing.get_context("forkserver").set_forkserver_preload([CHECKS_MODULE])
        self._lock = threading.Condition()
        self._lanes = [self._start() for _ in range(processes)]
        self._homes: LRUCache[str, int] = LRUCache(HOMES_KEPT)
        self._uses = itertools.count(1)
        self.last_pid: int | None = None  # the process that ran the last validation
        self.replaced = 0  # processes replaced for their memory
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

    @staticmethod
    def _start() -> _Lane:
        """A new process, warming up at once."""
        context = multiprocessing.get_context("forkserver")
        executor = ProcessPoolExecutor(1, mp_context=context, initializer=_lower_priority,
                                       initargs=(os.getpid(),))
        return _Lane(executor, executor.submit(_warm))

    def wait_warm(self, timeout: float | None = None) -> list[int]:
        """Wait until every process has warmed up, for at most `timeout` seconds in all; the
        ids of the processes that did (one whose warm-up failed only starts its first job
        cold)."""
        with self._lock:
            futures = [lane.warm for lane in self._lanes]
        done, _ = wait(futures, timeout)
        return [f.result() for f in futures if f in done and f.exception() is None]

    def _take(self, mission: str) -> int:
        """A free process, the mission's last one if it is free, else the one idle longest."""
        with self._lock:
            while True:
                if not self._lanes:
                    raise RuntimeError("the validation pool was shut down")
                free = [i for i, lane in enumerate(self._lanes) if not lane.busy]
                if free:
                    break
                self._lock.wait()
            home = self._homes.get(mission)
            index = home if home in free else min(free, key=lambda i: self._lanes[i].used)
            lane = self._lanes[index]
            lane.busy, lane.used = True, next(self._uses)
            self._homes[mission] = index
            return index

    def _give_back(self, index: int) -> None:
        with self._lock:
            if index < len(self._lanes):
                self._lanes[index].busy = False
            self._lock.notify_all()

    def _replace(self, index: int, broken: ProcessPoolExecutor) -> None:
        """A new process in place of `broken`'s (unless another thread replaced it)."""
        with self._lock:
            lane = self._lanes[index] if index < len(self._lanes) else None
            if lane is None or lane.executor is not broken:
                return
            fresh = self._start()
            lane.executor, lane.warm = fresh.executor, fresh.warm
        broken.shutdown(wait=False, cancel_futures=True)

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
        index = self._take(orders.id)
        try:
            for attempt in (1, 2):
                executor = self._lanes[index].executor
                try:
                    if handed:
                        pid, rss, *result = executor.submit(
                            _validate_parts, orders, *handed).result()
                    else:
                        pid, rss, *result = executor.submit(_validate, orders).result()
                except BrokenProcessPool:  # the process died (killed, out of memory)
                    self._replace(index, executor)
                    if attempt == 2:
                        raise
                    continue
                self.last_pid = pid
                if rss > self.max_rss:
                    self.replaced += 1
                    self._replace(index, executor)
                return result[0] if len(result) == 1 else tuple(result)
        finally:
            self._give_back(index)
        raise AssertionError("unreachable")

    def shutdown(self) -> None:
        with self._lock:
            lanes, self._lanes = self._lanes, []
            self._lock.notify_all()
        for lane in lanes:
            lane.executor.shutdown(wait=True, cancel_futures=True)
