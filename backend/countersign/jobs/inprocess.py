"""The in-process runner for the embedded SQLite default: the same task function as the
procrastinate workers, on a small pool in this process (threads) or beside it (processes,
for simulations in parallel). Its queue is the database itself: `resume()` reschedules every
unfinished campaign's missing chunks, so a process killed mid-run loses nothing that was
stored and counts nothing twice when started again.

Jobs wait in one queue per campaign owner, taken in turn (one FIFO let one person's
two 10,000-simulation campaigns keep everyone else's small one queued for minutes). While
others wait, one owner runs at most `workers - 1` jobs at once (with two workers or more), as
validation's per-user queues do; alone, an owner uses every worker."""

from __future__ import annotations

import concurrent.futures as cf
import functools
import logging
import multiprocessing
import os
import threading
from collections import OrderedDict, deque
from collections.abc import Callable

from ..pool_lifetime import end_with
from ..store import campaigns as store
from ..store.db import Database
from .tasks import missing_chunks, run_chunk

log = logging.getLogger("countersign.campaigns")
MAX_WORKERS = 8
ATTEMPTS = 3

_process_database: Database | None = None


def _process_init(url: str, owner_pid: int) -> None:
    global _process_database
    end_with(owner_pid)
    _process_database = Database(url)


def _process_chunk(campaign_id: str, start: int, stop: int) -> int:
    assert _process_database is not None
    return _attempts(_process_database, campaign_id, start, stop, None)


def _attempts(database: Database, campaign_id: str, start: int, stop: int,
              on_stored: Callable[[int], None] | None) -> int:
    """The job, tried ATTEMPTS times (as procrastinate's retry); then the campaign fails."""
    for attempt in range(1, ATTEMPTS + 1):
        try:
            return run_chunk(database, campaign_id, start, stop, on_stored=on_stored)
        except Exception as exc:
            log.warning("campaign %s job [%d, %d) attempt %d failed: %r", campaign_id, start,
                        stop, attempt, exc)
            if attempt == ATTEMPTS:
                with database.session() as db:
                    store.fail(db, campaign_id, f"a job failed {ATTEMPTS} times: "
                               f"{type(exc).__name__}: {exc}")
                raise
    return 0


class InProcessRunner:
    def __init__(self, database: Database, *, workers: int = 1, processes: bool = False,
                 on_stored: Callable[[int], None] | None = None) -> None:
        if not 1 <= workers <= MAX_WORKERS:
            raise ValueError(f"workers must be from 1 to {MAX_WORKERS}")
        self.database = database
        self.on_stored = on_stored
        self.workers = workers
        self._lock = threading.Condition()
        self._futures: list[cf.Future[int]] = []
        # Owner (user id, None for the command line) -> their waiting jobs, in turn order.
        self._queues: OrderedDict[int | None, deque[tuple[str, int, int]]] = OrderedDict()
        self._running: dict[int | None, int] = {}
        self._closed = False
        self._pool: cf.Executor
        if processes:
            # Not fork: the caller may run threads (the web server), which fork would copy
            # in whatever state they are.
            context = multiprocessing.get_context("spawn")
            self._pool = cf.ProcessPoolExecutor(workers, mp_context=context,
                                                initializer=_process_init,
                                                initargs=(database.url, os.getpid()))
            self._processes = True
        else:
            self._pool = cf.ThreadPoolExecutor(workers, thread_name_prefix="campaign")
            self._processes = False

    def enqueue(self, campaign_id: str, chunks: list[tuple[int, int]]) -> None:
        with self.database.session(write=False) as db:
            owner = store.get(db, campaign_id).owner_id
        with self._lock:
            queue = self._queues.setdefault(owner, deque())
            queue.extend((campaign_id, start, stop) for start, stop in chunks)
            self._dispatch()

    def _dispatch(self) -> None:
        """Start waiting jobs while workers are free: owners in turn, each within its share.
        Called with the lock held."""
        share = max(1, self.workers - 1)
        while not self._closed and sum(self._running.values()) < self.workers:
            waiting = [o for o, queue in self._queues.items() if queue]
            if not waiting:
                return
            # Within its share first; past it only when nobody else waits (a lone campaign,
            # the command line's, uses every worker). The command line's owner is None, so
            # None cannot mean "nobody".
            within = [o for o in waiting if self._running.get(o, 0) < share]
            if within:
                owner = within[0]
            elif len(waiting) == 1:
                owner = waiting[0]
            else:
                return
            queue = self._queues.pop(owner)
            campaign_id, start, stop = queue.popleft()
            if queue:
                self._queues[owner] = queue  # to the back of the turn order
            self._running[owner] = self._running.get(owner, 0) + 1
            if self._processes:
                future = self._pool.submit(_process_chunk, campaign_id, start, stop)
            else:
                future = self._pool.submit(_attempts, self.database, campaign_id, start,
                                           stop, self.on_stored)
            self._futures.append(future)
            future.add_done_callback(functools.partial(self._finished, owner))

    def _finished(self, owner: int | None, future: cf.Future[int]) -> None:
        with self._lock:
            self._running[owner] -= 1
            if not self._running[owner]:
                del self._running[owner]
            self._dispatch()
            self._lock.notify_all()
        self._report(future)

    def idle(self) -> bool:
        """Nothing running and nothing waiting: what was enqueued has ended, one way or
        another (a job that failed every attempt, or a pool whose processes died)."""
        with self._lock:
            return not self._running and not any(self._queues.values())

    def waiting(self) -> int:
        """Jobs queued and not started."""
        with self._lock:
            return sum(len(queue) for queue in self._queues.values())

    def resume(self) -> list[str]:
        """Schedule what every unfinished campaign still lacks; their ids."""
        with self.database.session(write=False) as db:
            ids = [row.id for row in store.unfinished(db)]
        for campaign_id in ids:
            chunks = missing_chunks(self.database, campaign_id)
            if chunks:
                self.enqueue(campaign_id, chunks)
            else:
                run_chunk(self.database, campaign_id, 0, 0)  # all stored: just seal it
        return ids

    def wait(self, timeout: float | None = None) -> None:
        """Until every job enqueued so far has run (or `timeout` seconds)."""
        with self._lock:
            self._lock.wait_for(lambda: self._closed or (not self._running and not any(
                self._queues.values())), timeout=timeout)

    def close(self) -> None:
        with self._lock:
            self._closed = True
            self._queues.clear()
            self._lock.notify_all()
        self._pool.shutdown(wait=False, cancel_futures=True)

    @staticmethod
    def _report(future: cf.Future[int]) -> None:
        if not future.cancelled() and future.exception() is not None:
            log.error("campaign job failed: %r", future.exception())
