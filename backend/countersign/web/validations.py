"""What a server process asks of a validation pool, whichever pool serves it.

A server process validates in a pool of its own (validation_pool.ValidationPool) or, with
`serve --workers N`, in the host's one pool through a client (host_pool.HostPoolClient), whose
calls travel through a proxy (host_pool._PoolProxy) to the host's ValidationPool. The three
were kept alike by hand, and a method added to one (`wait_warm`) had to be added to the others
by whoever noticed. Typed against these protocols, mypy names the method one of them lacks.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    from ..orders.model import Orders
    from ..verify.parts import PartKeys


class ValidationCalls(Protocol):
    """The calls a pool answers: what the host's pool serves to its clients' proxies. Each
    validation is queued for `submitter`, by default the SUBMITTER of the calling context
    (validation_pool.py)."""

    def validate(self, orders: Orders, submitter: str | None = None) -> dict[str, Any]:
        """The report of `verify.validate(orders)`, computed in a pool process."""
        ...

    def validate_parts(self, orders: Orders, known: dict[str, Any], keys: PartKeys,
                       orders_digest: str, submitter: str | None = None
                       ) -> tuple[dict[str, Any], dict[str, Any]]:
        """As validate, handing over the report parts already known: the report, and the
        parts the process computed."""
        ...

    def running(self, submitter: str) -> int:
        """How many validations of this submitter are in a process now."""
        ...

    def pending(self, submitter: str) -> int:
        """How many validations of this submitter are running or waiting for their turn."""
        ...

    def wait_warm(self, timeout: float | None = None) -> list[int]:
        """Wait for the processes to warm up; the ids of those that did."""
        ...


class ValidationPools(ValidationCalls, Protocol):
    """A pool as the app holds it for as long as it serves: the calls, and an end."""

    def shutdown(self) -> None:
        """Stop what this server process started (a client leaves the host's pool running)."""
        ...


# The calls a proxy forwards to the host's pool (multiprocessing's `_exposed_`).
CALLS: tuple[str, ...] = tuple(name for name in vars(ValidationCalls)
                               if not name.startswith("_"))
