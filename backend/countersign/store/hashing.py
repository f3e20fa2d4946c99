"""Argon2 with bounded concurrency, in a low-priority process while a server runs.

An Argon2 hash is tens of milliseconds of CPU and 64 MiB of memory, and argon2-cffi's default
(parallelism 4) runs each one in four threads of its own. Run in the web server's worker
threads, a flood of anonymous logins took every core from the event loop: 96 of them pushed
/api/health to 17.8 s, and still 6.7 s with hashes one at a time, since one hash's
four threads fill both cores of a 2-core machine.

So a running server (`use_processes`, from the app's lifespan) hashes in processes of its own
at the lowest priority (nice 19): the scheduler gives the web process the core whenever it
wants one, and hashes take the rest. At most `waiting` hashes are queued or running; a login
beyond that is refused at once (HashingBusy, 503 with Retry-After) instead of holding a
request thread. Without processes (the CLI, in-process test clients) hashes run in the calling
thread, one `slots` at a time.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import threading
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Literal

from argon2 import PasswordHasher

from ..errors import Unavailable
from ..pool_lifetime import end_with

HASH_SLOTS = max(1, (os.cpu_count() or 1) - 1)
HASH_NICENESS = 19
# Hashes queued or running at once per server process: a few hundred milliseconds of waiting
# at most on a quiet machine; more would only hold request threads for an attacker.
HASH_WAITING = 8


class HashingBusy(Unavailable):
    """Every place in the password-hashing queue is taken (a login flood): retry shortly."""

    retry_after_s = 1


def _lowest_priority(owner_pid: int) -> None:
    end_with(owner_pid)
    with contextlib.suppress(OSError):  # not permitted: hash at the server's priority
        os.nice(HASH_NICENESS)


def _hash(parameters: dict[str, Any], password: str | bytes) -> str:
    return PasswordHasher(**parameters).hash(password)


def _verify(parameters: dict[str, Any], stored: str | bytes, password: str | bytes) -> bool:
    # argon2's exceptions pickle, so a wrong password raises in the caller as in a thread.
    return PasswordHasher(**parameters).verify(stored, password)


class BoundedHasher(PasswordHasher):
    """argon2-cffi's PasswordHasher whose hash and verify take one of `slots` at a time, or
    run in a low-priority process pool with a bounded queue (`use_processes`)."""

    def __init__(self, *args: Any, slots: int = HASH_SLOTS, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.slots = threading.BoundedSemaphore(slots)
        self._argon2_parameters = {"time_cost": self.time_cost, "memory_cost": self.memory_cost,
                            "parallelism": self.parallelism, "hash_len": self.hash_len,
                            "salt_len": self.salt_len, "type": self.type}
        self._lock = threading.Lock()
        self._executor: ProcessPoolExecutor | None = None
        self._users = 0  # apps running with processes (the test suite starts several)
        self._waiting_limit = HASH_WAITING
        self._in_flight = 0
        self._started: Future[int] | None = None

    def use_processes(self, processes: int = 1, waiting: int = HASH_WAITING) -> None:
        """Hash in `processes` low-priority processes from now until `stop_processes`."""
        with self._lock:
            self._users += 1
            if self._executor is None:
                self._executor = ProcessPoolExecutor(
                    processes, mp_context=multiprocessing.get_context("forkserver"),
                    initializer=_lowest_priority, initargs=(os.getpid(),))
                # Start the process now; until it is up, hashes run in threads as before
                # (a sign-in right after a restart need not wait for a process to start).
                self._started = self._executor.submit(os.getpid)
            self._waiting_limit = waiting

    def stop_processes(self) -> None:
        with self._lock:
            self._users = max(0, self._users - 1)
            executor = self._executor if self._users == 0 else None
            if executor is not None:
                self._executor = self._started = None
        if executor is not None:
            executor.shutdown(wait=True, cancel_futures=True)

    def has_room(self) -> bool:
        """Whether a hash asked for now would be queued (callers check before they count an
        attempt, so that a refused login costs the account nothing)."""
        with self._lock:
            return not self._in_processes() or self._in_flight < self._waiting_limit

    def _in_processes(self) -> bool:
        return (self._executor is not None and self._started is not None
                and self._started.done())

    def hash(self, password: str | bytes, *, salt: bytes | None = None) -> str:
        if salt is None:
            future = self._submit(_hash, self._argon2_parameters, password)
            if future is not None:
                return str(self._result(future))
        with self.slots:
            return super().hash(password, salt=salt)

    def verify(self, hash: str | bytes, password: str | bytes) -> Literal[True]:
        future = self._submit(_verify, self._argon2_parameters, hash, password)
        if future is not None:
            self._result(future)
            return True
        with self.slots:
            return super().verify(hash, password)

    def _submit(self, function: Any, *args: Any) -> Future[Any] | None:
        with self._lock:
            if self._executor is None or not self._in_processes():
                return None
            if self._in_flight >= self._waiting_limit:
                raise HashingBusy("the server is busy checking passwords; retry in a moment")
            self._in_flight += 1
            try:
                future = self._executor.submit(function, *args)
            except (BrokenProcessPool, RuntimeError):
                self._in_flight -= 1
                return None  # a dead or closing pool: hash here rather than fail the login
        future.add_done_callback(self._done)
        return future

    def _done(self, _future: Future[Any]) -> None:
        with self._lock:
            self._in_flight -= 1

    def _result(self, future: Future[Any]) -> Any:
        try:
            return future.result()
        except BrokenProcessPool:  # the hashing process died (killed, out of memory)
            with self._lock:
                self._executor = None  # the next hash runs here; a restart brings processes
            raise HashingBusy("password checking restarted; retry in a moment") from None


# The one hasher of the process: every password check goes through it (login_throttle.py).
HASHER = BoundedHasher()
