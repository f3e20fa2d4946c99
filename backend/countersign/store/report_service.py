"""The report service: computes validation reports for the store, once per digest.

It owns what used to be module state: the single-flight locks (many requests asking for one
digest at once validate it once), the last reports computed here, the reuse of a report across
description-only edits, the orders digests of recently validated request bodies (POST
/validate), and the validator, which by default runs `verify.validate` in the
calling thread and which the web app replaces with its pool of validation processes while it
runs. One service belongs to one `Database` (`database.reports`), so two apps in one process,
as in the test suite, share nothing.

It lives in the store, not in `verify`, because it is state around the pure check: the store
consults it on a cache miss of its table of reports, and the pool is injected as a plain
callable so the store never imports the web layer.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ..verify.reuse import ReportReuse

if TYPE_CHECKING:
    from ..orders.model import Orders

Validator = Callable[["Orders"], dict[str, Any]]
RECENT_REPORTS = 256
BODY_DIGESTS_KEPT = 1024


def validate_here(orders: Orders) -> dict[str, Any]:
    """The report of `verify.validate(orders)`, computed in the calling thread."""
    # Imported on first use: the checks pull in z3 and rdflib, which opening a database (and
    # every command that does) need not pay for.
    from ..verify.report import validate

    return validate(orders).to_json()


class ReportService:
    def __init__(self, validator: Validator | None = None,
                 reuse: ReportReuse | None = None) -> None:
        # None: validate in the calling thread. The web app sets its pool's `validate` for as
        # long as the pool runs (web/app.py lifespan) and puts None back when it stops.
        self.validator = validator
        self._reuse = reuse if reuse is not None else ReportReuse()
        self._in_flight: dict[str, threading.Lock] = {}
        self._guard = threading.Lock()
        # The last reports computed here, so that requests that waited on a digest reuse it.
        self._recent: OrderedDict[str, dict[str, Any]] = OrderedDict()
        # The orders digest of recently validated request bodies, by the bodies' SHA-256.
        self._bodies: OrderedDict[bytes, str] = OrderedDict()

    def report(self, key: str, orders: Orders) -> dict[str, Any]:
        """The report of these orders (digest `key`), validated once even when many requests
        ask at once."""
        with self._guard:
            lock = self._in_flight.setdefault(key, threading.Lock())
        with lock:
            done = self._recent.get(key)
            if done is None:
                # An edit of descriptions only is answered from the last report of the same
                # facts.
                done = self._reuse.report(orders, key, self._full)
                with self._guard:
                    self._recent[key] = done
                    while len(self._recent) > RECENT_REPORTS:
                        self._recent.popitem(last=False)
        with self._guard:
            self._in_flight.pop(key, None)
        return done

    def _full(self, orders: Orders) -> dict[str, Any]:
        validator = self.validator
        return validator(orders) if validator is not None else validate_here(orders)

    def body_digest(self, body_sha256: bytes) -> str | None:
        """The orders digest of a request body validated lately, or None."""
        with self._guard:
            return self._bodies.get(body_sha256)

    def remember_body(self, body_sha256: bytes, orders_digest: str) -> None:
        with self._guard:
            self._bodies[body_sha256] = orders_digest
            while len(self._bodies) > BODY_DIGESTS_KEPT:
                self._bodies.popitem(last=False)

    def clear(self) -> None:
        with self._guard:
            self._recent.clear()
            self._bodies.clear()
        self._reuse.clear()
