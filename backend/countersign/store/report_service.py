"""The report service: computes validation reports for the store, once per digest.

It owns what used to be module state: the single-flight locks (many requests asking for one
digest at once validate it once), the last reports computed here, the reuse of a report across
description-only edits, the orders digests of recently validated request bodies (POST
/validate), and the validator, which by default runs `verify.validate` in the
calling thread and which the web app replaces with its pool of validation processes while it
runs. One service belongs to one `Database` (`database.reports`), so two apps in one process,
as in the test suite, share nothing.

Every report it hands out was made by the checks of this process (verify.fingerprint): its
caches hold the reports of one checker fingerprint and are emptied when that changes, and a
report from a validator running other checks (a pool process started from replaced files) is
made again here.

It lives in the store, not in `verify`, because it is state around the pure check: the store
consults it on a cache miss of its table of reports, and the pool is injected as a plain
callable so the store never imports the web layer.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from cachetools import LRUCache

from ..verify import fingerprint
from ..verify.reuse import ReportReuse

if TYPE_CHECKING:
    from ..orders.model import Orders
    from ..verify.parts import PartKeys, PartsCache

Validator = Callable[["Orders"], dict[str, Any]]
# (orders, the parts known for them by key, their keys, their digest) -> (report, its parts):
# a validator that computes only the parts not handed to it (the pool's, in another process).
PartsValidator = Callable[["Orders", dict[str, Any], "PartKeys", str],
                          tuple[dict[str, Any], dict[str, Any]]]
PARTS_KEPT = 512  # four per mission version: the last versions of about a hundred missions
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
        # Set with the pool (use_pool): the validator that takes the report parts known here.
        self.parts_validator: PartsValidator | None = None
        self._paired: Validator | None = None
        self._parts: PartsCache | None = None
        self._reuse = reuse if reuse is not None else ReportReuse()
        self._in_flight: dict[str, threading.Lock] = {}
        self._guard = threading.Lock()
        # The last reports computed here, so that requests that waited on a digest reuse it.
        self._recent: LRUCache[str, dict[str, Any]] = LRUCache(RECENT_REPORTS)
        # The orders digest of recently validated request bodies, by the bodies' SHA-256.
        self._bodies: LRUCache[bytes, str] = LRUCache(BODY_DIGESTS_KEPT)
        # The checker fingerprint the caches above hold reports of.
        self._checker: str | None = None

    def report(self, key: str, orders: Orders, keys: PartKeys | None = None
               ) -> dict[str, Any]:
        """The report of these orders (`key` is their digest, orders.canonical.digest, which
        the report carries), validated once even when many requests ask at once. `keys`, the
        orders' part keys when the caller made them already (verify.parts)."""
        checker = self._current_checker()
        with self._guard:
            lock = self._in_flight.setdefault(key, threading.Lock())
        with lock:
            with self._guard:
                done = self._recent.get(key)
            if done is None:
                # An edit of descriptions only is answered from the last report of the same
                # facts.
                part_keys = keys if keys is not None else self._keys(orders)
                done = self._reuse.report(
                    orders, key, lambda o: self._full(o, key, part_keys),
                    checked=part_keys.core)
                if done.get("checker") != checker:
                    done = validate_here(orders)
                with self._guard:
                    self._recent[key] = done
        with self._guard:
            self._in_flight.pop(key, None)
        return done

    def recent(self, key: str) -> dict[str, Any] | None:
        """The report of this orders digest if this service made it lately (by the current
        checks), else None: what the store holds for it, without decoding the stored copy."""
        self._current_checker()
        with self._guard:
            return self._recent.get(key)

    def _current_checker(self) -> str:
        """This process's checker fingerprint; what was cached under another is dropped (the
        orders digests of bodies too: the digest is computed by checked code)."""
        checker = fingerprint.checker_fingerprint()
        if checker != self._checker:
            self.clear()
            self._checker = checker
        return checker

    def use_pool(self, validator: Validator | None,
                 parts_validator: PartsValidator | None = None) -> None:
        """Validate with `validator` (None: in the calling thread); `parts_validator`, the
        same pool's, is used instead while `validator` is the one set here."""
        self.validator = validator
        self.parts_validator = parts_validator
        self._paired = validator

    @staticmethod
    def _keys(orders: Orders) -> PartKeys:
        from ..verify.parts import part_keys

        return part_keys(orders)

    def parts(self) -> PartsCache:
        """The report parts computed for this service, by the digest of what they read."""
        if self._parts is None:
            from ..verify.parts import PartsCache

            with self._guard:
                if self._parts is None:
                    self._parts = PartsCache(PARTS_KEPT)
        return self._parts

    def _full(self, orders: Orders, key: str, keys: PartKeys) -> dict[str, Any]:
        """The report, computing only the parts (verify.parts) no earlier report here has."""
        validator = self.validator
        parts = self.parts()
        if validator is None:
            from ..verify.report import validate

            return validate(orders, parts=parts, keys=keys, orders_digest=key).to_json()
        if self.parts_validator is None or validator != self._paired:
            return validator(orders)  # a validator of its own (tests): the whole report
        report, computed = self.parts_validator(orders, parts.items(keys), keys, key)
        parts.update(computed)
        return report

    def body_digest(self, body_sha256: bytes) -> str | None:
        """The orders digest of a request body validated lately, or None."""
        self._current_checker()
        with self._guard:
            return self._bodies.get(body_sha256)

    def remember_body(self, body_sha256: bytes, orders_digest: str) -> None:
        with self._guard:
            self._bodies[body_sha256] = orders_digest

    def clear(self) -> None:
        with self._guard:
            self._recent.clear()
            self._bodies.clear()
        self._reuse.clear()
        if self._parts is not None:
            self._parts.clear()
