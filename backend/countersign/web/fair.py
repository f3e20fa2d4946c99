"""Fair, bounded work per user: who a validation is queued for, and rate limits on
the expensive routes.

A route that validates, reads, imports or plans names its kind here; the dependency that
results charges the signed-in user's token bucket for that kind and answers 429 with
Retry-After and a problem body when it is empty, and records the user as the submitter of
the validations the request runs (validation_pool.SUBMITTER), so that each user has a queue of
their own in front of the validation processes. Buckets live in the server process: with
`--workers N` a user may get up to N times the rate, which is still bounded.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Coroutine, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from fastapi import Depends, HTTPException, Request

from .deps import CurrentPrincipal
from .validation_pool import SUBMITTER


@dataclass(frozen=True)
class Rate:
    burst: int  # requests allowed at once
    per_second: float  # refill


# Generous enough for an editor re-validating at every keystroke pause and a CI job, small
# enough that one user cannot keep every core busy. A plan also holds a slot while it runs.
RATES: dict[str, Rate] = {
    "validate": Rate(burst=120, per_second=20.0),
    "read": Rate(burst=60, per_second=5.0),
    "import": Rate(burst=60, per_second=5.0),
    "plan": Rate(burst=20, per_second=1.0),
}
PLANS_PER_USER = 1  # plans one user may run at once in a process
PLANS_AT_ONCE = 2  # plans every user together may run at once in a process


class TooManyRequests(HTTPException):
    def __init__(self, detail: str, retry_after_s: float) -> None:
        super().__init__(429, detail, headers={"Retry-After": str(max(1, math.ceil(
            retry_after_s)))})


class RateLimiter:
    """Token buckets per (user, kind)."""

    def __init__(self, rates: dict[str, Rate] | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.rates = dict(rates or RATES)
        self._clock = clock
        self._lock = threading.Lock()
        self._buckets: dict[tuple[str, str], tuple[float, float]] = {}  # tokens, at

    def charge(self, user: str, kind: str) -> float:
        """0 when the request may go ahead (a token is taken), else seconds until one is."""
        rate = self.rates[kind]
        now = self._clock()
        with self._lock:
            tokens, at = self._buckets.get((user, kind), (float(rate.burst), now))
            tokens = min(float(rate.burst), tokens + (now - at) * rate.per_second)
            if tokens >= 1.0:
                self._buckets[(user, kind)] = (tokens - 1.0, now)
                return 0.0
            self._buckets[(user, kind)] = (tokens, now)
            return (1.0 - tokens) / rate.per_second


class PlanSlots:
    """Plans run in the server's threads and hold the interpreter lock: a few at a time."""

    def __init__(self, per_user: int = PLANS_PER_USER, total: int = PLANS_AT_ONCE) -> None:
        self.per_user = per_user
        self.total = total
        self._lock = threading.Lock()
        self._running: dict[str, int] = {}

    @contextmanager
    def hold(self, user: str) -> Iterator[None]:
        with self._lock:
            if self._running.get(user, 0) >= self.per_user:
                raise TooManyRequests("a plan of yours is still being solved; wait for it", 1)
            if sum(self._running.values()) >= self.total:
                raise TooManyRequests("the planner is busy with other users' plans; retry "
                                      "in a moment", 2)
            self._running[user] = self._running.get(user, 0) + 1
        try:
            yield
        finally:
            with self._lock:
                self._running[user] -= 1
                if not self._running[user]:
                    del self._running[user]


def limiter_of(request: Request) -> RateLimiter:
    limiter: RateLimiter = request.app.state.rate_limiter
    return limiter


def user_key(principal: CurrentPrincipal) -> str:
    return f"user:{principal.user.id}"


def limited(kind: str) -> Callable[..., Coroutine[Any, Any, None]]:
    """A route dependency: charge the user's `kind` bucket and queue their validations as
    theirs. Async so that SUBMITTER is set in the request's own context, which the thread
    running a synchronous endpoint copies."""
    if kind not in RATES:
        raise ValueError(f"unknown rate kind {kind!r}")

    async def dependency(request: Request, principal: CurrentPrincipal) -> None:
        user = user_key(principal)
        wait = limiter_of(request).charge(user, kind)
        if wait > 0:
            raise TooManyRequests(f"too many {kind} requests; retry in {math.ceil(wait)} s",
                                  wait)
        SUBMITTER.set(user)

    return dependency


async def _submitter(principal: CurrentPrincipal) -> None:
    SUBMITTER.set(user_key(principal))


def with_limit(route: dict[str, Any], kind: str | None) -> dict[str, Any]:
    """Route keyword arguments (allow(...)'s) plus the rate limit of `kind`, or only the
    submitter when `kind` is None (routes that validate a user's own draft)."""
    dependency = limited(kind) if kind is not None else _submitter
    return {**route, "dependencies": [*route.get("dependencies", ()), Depends(dependency)]}
