"""One validation pool per host, shared by every server process of `serve --workers N`.

The fair queue of validation_pool.py orders the validations of the process that owns the
pool. With a pool in each of two server processes, a user flooding heavy validations ran one
in each (each pool leaves its other process free, but both cores were busy) and another user's
small edit waited for a core: p99 1.3 s with two server processes against 0.4 s with one.

So with several server processes the pool lives in a process of its own, started by the
command before gunicorn forks its workers, and every worker hands its validations over a Unix
socket (multiprocessing.managers: the orders pickled as they already are for a pool process;
the connection authenticated with a random key held only in memory). The one fair queue then
sees every user's work on the host: a user runs at most `processes - 1` validations at once
whichever server process their requests reach. It does not depend on the database, so it works
the same on SQLite and PostgreSQL. Several hosts on one PostgreSQL each queue their own.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import secrets
import shutil
import tempfile
import threading
from dataclasses import dataclass
from multiprocessing.managers import BaseManager, BaseProxy
from typing import TYPE_CHECKING, Any

from ..orders.model import Orders
from ..pool_lifetime import end_with
from .validation_pool import SUBMITTER, WARM_WAIT_S, ValidationPool
from .validations import CALLS, ValidationCalls

if TYPE_CHECKING:
    from ..verify.parts import PartKeys

logger = logging.getLogger("countersign.validation")

_POOL: ValidationPool | None = None  # in the host process only


def _start_pool(processes: int, owner_pid: int) -> None:
    """In the host process, before it serves: the pool, and an end with the command's process
    (a SIGKILLed gunicorn master must not leave the host and its validation processes)."""
    global _POOL
    end_with(owner_pid)
    _POOL = ValidationPool(processes)


def _the_pool() -> ValidationPool:
    if _POOL is None:
        raise RuntimeError("the validation host has no pool")
    return _POOL


class _PoolProxy(BaseProxy):
    """The pool's methods a server process calls (validations.ValidationCalls, checked by
    mypy through _proxy); each calling thread has a connection of its own (BaseProxy keeps
    them per thread), so validations wait for their turn in parallel."""

    _exposed_ = CALLS

    def _call(self, method: str, *args: Any) -> Any:
        call: Any = self._callmethod  # typeshed has it return None; it returns the result
        return call(method, args)

    def validate(self, orders: Orders, submitter: str | None = None) -> dict[str, Any]:
        report: dict[str, Any] = self._call("validate", orders, submitter)
        return report

    def validate_parts(self, orders: Orders, known: dict[str, Any], keys: PartKeys,
                       orders_digest: str, submitter: str | None = None
                       ) -> tuple[dict[str, Any], dict[str, Any]]:
        result: tuple[dict[str, Any], dict[str, Any]] = self._call(
            "validate_parts", orders, known, keys, orders_digest, submitter)
        return result

    def running(self, submitter: str) -> int:
        return int(self._call("running", submitter))

    def pending(self, submitter: str) -> int:
        return int(self._call("pending", submitter))

    def wait_warm(self, timeout: float | None = None) -> list[int]:
        return list(self._call("wait_warm", timeout))


class _HostManager(BaseManager):
    pass


_HostManager.register("pool", callable=_the_pool, proxytype=_PoolProxy)


def _proxy(manager: _HostManager) -> ValidationCalls:
    """The host's pool, through a proxy typed as the calls it must forward."""
    proxy: _PoolProxy = manager.pool()  # type: ignore[attr-defined]
    return proxy


@dataclass(frozen=True)
class HostPoolAddress:
    """Where the host's pool listens and the key to talk to it (handed to each worker in the
    app factory's closure, never through the environment)."""

    socket: str
    authkey: bytes

    def __repr__(self) -> str:  # the key stays out of logs and tracebacks
        return f"HostPoolAddress({self.socket!r})"


class HostPool:
    """The command's handle on the host process: start it, and stop it when the server ends."""

    def __init__(self, processes: int) -> None:
        self._folder = tempfile.mkdtemp(prefix="countersign-pool-")  # 0700: ours only
        self.address = HostPoolAddress(os.path.join(self._folder, "pool"),
                                       secrets.token_bytes(32))
        # spawn: the host starts from a clean interpreter, holding nothing of the command's
        # (its database connections, its gunicorn state).
        self._manager = _HostManager(address=self.address.socket,
                                     authkey=self.address.authkey,
                                     ctx=multiprocessing.get_context("spawn"))
        self._manager.start(_start_pool, (processes, os.getpid()))
        # Its processes warm up before the server processes start: a command that ends early
        # (a taken port) then never stops the host while it is still starting them (their
        # start-up, cut short, wrote tracebacks into the server's log).
        _proxy(self._manager).wait_warm(WARM_WAIT_S)

    def stop(self) -> None:
        self._manager.shutdown()
        shutil.rmtree(self._folder, ignore_errors=True)


class HostPoolClient:
    """In a server process: the pool's calls (validations.ValidationPools), served by the
    host's pool, each validation queued for the SUBMITTER of the calling context.

    Should the host process end (killed, out of memory), validations go on in a pool of this
    server process's own, fair among its own requests only, rather than failing until the
    server is restarted."""

    def __init__(self, address: HostPoolAddress, processes: int) -> None:
        self.processes = processes
        manager = _HostManager(address=address.socket, authkey=address.authkey)
        manager.connect()
        self._pool = _proxy(manager)
        self._lock = threading.Lock()
        self._own: ValidationPool | None = None

    def _fallback(self, error: BaseException) -> ValidationPool:
        with self._lock:
            if self._own is None:
                logger.warning("the host's validation pool is gone (%s); validating in this "
                               "server process's own pool", type(error).__name__)
                self._own = ValidationPool(self.processes)
            return self._own

    def _served(self) -> ValidationCalls:
        return self._own if self._own is not None else self._pool

    def validate(self, orders: Orders, submitter: str | None = None) -> dict[str, Any]:
        who = SUBMITTER.get() if submitter is None else submitter
        try:
            return self._served().validate(orders, who)
        except (EOFError, OSError) as error:  # the connection to the host, not the checks
            return self._fallback(error).validate(orders, who)

    def validate_parts(self, orders: Orders, known: dict[str, Any], keys: PartKeys,
                       orders_digest: str, submitter: str | None = None
                       ) -> tuple[dict[str, Any], dict[str, Any]]:
        handed = (orders, known, keys, orders_digest,
                  SUBMITTER.get() if submitter is None else submitter)
        try:
            return self._served().validate_parts(*handed)
        except (EOFError, OSError) as error:
            return self._fallback(error).validate_parts(*handed)

    def running(self, submitter: str) -> int:
        return self._served().running(submitter)

    def pending(self, submitter: str) -> int:
        return self._served().pending(submitter)

    def wait_warm(self, timeout: float | None = None) -> list[int]:
        """Wait for the host's processes to warm up (every server process asks; the first
        to ask waits, the others find them warm)."""
        try:
            return self._served().wait_warm(timeout)
        except (EOFError, OSError) as error:
            return self._fallback(error).wait_warm(timeout)

    def shutdown(self) -> None:
        """The host's pool outlives a server process (gunicorn replaces one that dies) and
        ends with the command; only a fallback pool of this process's own ends here."""
        if self._own is not None:
            self._own.shutdown()
