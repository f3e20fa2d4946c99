"""Report parts, filed by the digest of exactly what their checks read.

`verify.validate` assembles a report from four parts:

- core: structure, paths, costs and budget, vehicle, text, geo, the rules' design checks,
  patterns and probabilities; they read everything but descriptions;
- meo: C1, C2, M6 and M7, which read the goals' ids, titles, successors and requirements,
  the terminals, the constraints and the vehicles (not costs, areas, norms, envelopes, ...);
- logic: EXPR, CONTRADICTION, NORM and VACUOUS, which read everything but descriptions and
  the goals' costs and outcome probabilities;
- properties: the path properties, which read what core reads.

A part's key is the SHA-256 of the checker fingerprint and the JSON of the orders with the
fields its checks do not read left out: the top-level fields as text, then each goal as the
SHA-256 of its text, kept by the goal's whole JSON text (an edit's other 999 goals cost a
lookup, with the text the orders' digest is made from too: orders.canonical.goal_texts). A key
that left out a field its checks do read would reuse a stale part:
tests/verify/test_incremental.py compares incremental reports with reports from scratch over
random edits of every field, and fails when a field is wrongly left out.
"""

from __future__ import annotations

import hashlib
import json
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from cachetools import LRUCache

from ..orders.canonical import goal_texts, orders_to_json
from ..orders.model import Orders
from .fingerprint import checker_fingerprint

PART_NAMES = ("core", "meo", "logic", "properties")

# Fields each part's checks do not read, at the top of the orders and in each goal.
_NOT_READ: dict[str, tuple[frozenset[str], frozenset[str]]] = {
    "core": (frozenset({"description"}), frozenset({"description"})),
    "meo": (frozenset({"description", "norms", "areas", "charts", "properties"}),
            frozenset({"description", "cost", "p", "params", "envelope", "behavior", "area"})),
    "logic": (frozenset({"description"}), frozenset({"description", "cost", "p"})),
}


@dataclass(frozen=True)
class PartKeys:
    core: str
    meo: str
    logic: str
    properties: str

    def of(self, name: str) -> str:
        return str(getattr(self, name))


# The SHA-256 of each keyed part's view of a goal, by the goal's JSON text.
GOALS_KEPT = 200_000
_KEYED = tuple(_NOT_READ)
_goal_views: LRUCache[str, tuple[bytes, ...]] = LRUCache(GOALS_KEPT)
_goal_views_lock = threading.Lock()


def _views_of_goal(goal: Any, text: str) -> tuple[bytes, ...]:
    with _goal_views_lock:
        found = _goal_views.get(text)
    if found is None:
        found = tuple(
            hashlib.sha256(json.dumps(
                {k: v for k, v in goal.items() if k not in _NOT_READ[name][1]}
                if isinstance(goal, dict) else goal, ensure_ascii=False).encode()).digest()
            for name in _KEYED)
        with _goal_views_lock:
            _goal_views[text] = found
    return found


def part_keys(orders: Orders) -> PartKeys:
    """The key of each part of these orders' report. Keys are compared only within one
    version of the code, never stored."""
    return part_keys_of_json(orders_to_json(orders))


def part_keys_of_json(data: dict[str, Any], texts: Sequence[str] | None = None) -> PartKeys:
    """part_keys of orders made JSON data by orders_to_json; `texts` is goal_texts(data) when
    the caller made it already."""
    given = data.get("goals")
    goals = given if isinstance(given, list) else []
    # Goals not given and given as [] (or not as a list) keep keys of their own.
    shape = f"list {len(goals)}" if isinstance(given, list) else f"not a list: {given!r}"
    if texts is None:
        texts = goal_texts(data)
    views = [_views_of_goal(goal, text) for goal, text in zip(goals, texts, strict=True)]
    # With the checks' fingerprint: parts travel between processes (the web process hands
    # its parts to a validation process), which may run other checks after an upgrade.
    checker = checker_fingerprint().encode()
    keys: dict[str, str] = {}
    for index, name in enumerate(_KEYED):
        top = json.dumps({k: v for k, v in data.items()
                          if k != "goals" and k not in _NOT_READ[name][0]},
                         ensure_ascii=False).encode()
        digest = hashlib.sha256(b"|".join((checker, str(len(top)).encode(), top, shape.encode())))
        for view in views:
            digest.update(view[index])
        keys[name] = f"{name}:{digest.hexdigest()}"
    keys["properties"] = "properties:" + keys["core"].removeprefix("core:")
    return PartKeys(**keys)


class PartsCache:
    """Report parts by key, bounded (least recently used first out) and thread-safe. Values
    are shared between reports: never mutate one."""

    keeps = True

    def __init__(self, max_entries: int = 256) -> None:
        self._data: LRUCache[str, Any] = LRUCache(max_entries)
        self._lock = threading.Lock()
        self.max_entries = max_entries
        self.hits = 0
        self.misses = 0

    def get(self, name: str, key: str) -> Any:
        with self._lock:
            value = self._data.get(key)
            if value is None:
                self.misses += 1
            else:
                self.hits += 1
            return value

    def put(self, name: str, key: str, value: Any) -> None:
        with self._lock:
            self._data[key] = value

    def items(self, keys: PartKeys) -> dict[str, Any]:
        """The parts held for these keys, by key (to hand to another process)."""
        with self._lock:
            return {k: self._data[k] for k in (keys.of(n) for n in PART_NAMES)
                    if k in self._data}

    def update(self, parts: dict[str, Any]) -> None:
        for key, value in parts.items():
            self.put(key.split(":", 1)[0], key, value)

    def clear(self) -> None:
        with self._lock:
            self._data.clear()


class NoParts(PartsCache):
    """Keeps nothing, so validating with it computes no keys: for a process that validates
    once and ends (the command line), where the keys (a serialisation of the orders per part
    and the checker fingerprint's read of the package) would cost more than they can save."""

    keeps = False

    def get(self, name: str, key: str) -> Any:
        return None

    def put(self, name: str, key: str, value: Any) -> None:
        return None


# The keys validate uses with a store that keeps nothing (NoParts): it never reads them.
UNKEYED = PartKeys("", "", "", "")

# One cache per process: in-process callers (command line, tests, the validation processes)
# reuse the parts of earlier validations of the same mission.
SHARED_PARTS = PartsCache()

__all__ = ["PART_NAMES", "SHARED_PARTS", "UNKEYED", "NoParts", "PartKeys", "PartsCache",
           "part_keys", "part_keys_of_json"]
