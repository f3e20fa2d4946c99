"""Reports reused across edits that change no checked fact.

No check reads a description (the mission's or a goal's): the findings, path counts and costs
of orders that differ only there are the same. A report is therefore filed under the digest of
its orders with every description blanked, and an edit whose blanked digest was seen is
answered from that report with only its digest replaced. Titles are not in this list: logic
findings quote goal labels. Tests check the reused report equals a full validation.

Reports are shared, never mutated (the report service hands one dict to every request that
asked for its digest): a reused report is a new top-level dict around the same findings, and
the report kept is the one returned. Deep copies of a thousand findings, one per validation,
cost a 1,000-goal edit more CPU than storing its report.
"""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Callable
from typing import Any

import rfc8785
from cachetools import LRUCache

from ..orders.canonical import orders_to_json
from ..orders.model import Orders


def checked_digest(orders: Orders) -> str:
    """The digest of what the checks read: the orders without descriptions (written or not)."""
    data = orders_to_json(orders)
    data.pop("description", None)
    for goal in data.get("goals", []):
        goal.pop("description", None)
    return "sha256:" + hashlib.sha256(bytes(rfc8785.dumps(data))).hexdigest()


class ReportReuse:
    """The last reports by checked digest, bounded and safe to share between threads."""

    def __init__(self, max_entries: int = 256) -> None:
        self._reports: LRUCache[str, dict[str, Any]] = LRUCache(max_entries)
        self._lock = threading.Lock()

    def report(self, orders: Orders, orders_digest: str,
               validate: Callable[[Orders], dict[str, Any]],
               checked: str | None = None) -> dict[str, Any]:
        """The report of these orders: reused when only descriptions changed, else validated.
        `checked` is a digest of the orders without descriptions when the caller has one
        (verify.parts' core key), else checked_digest is computed."""
        key = checked if checked is not None else checked_digest(orders)
        with self._lock:
            found = self._reports.get(key)
        if found is not None:
            return {**found, "digest": orders_digest}
        done = validate(orders)
        with self._lock:
            self._reports[key] = done
        return done

    def clear(self) -> None:
        with self._lock:
            self._reports.clear()

