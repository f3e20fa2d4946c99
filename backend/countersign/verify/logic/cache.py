"""Unit results cached by the digest of their items' sources."""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Iterable
from operator import attrgetter
from weakref import WeakKeyDictionary

from cachetools import LRUCache

from ...orders.model import Orders
from .constants import VERSION
from .items import Item
from .model import LogicModel


class LogicCache:
    """Unit results by the digest of their inputs; thread-safe and bounded (least recently used
    entries go first). Hold one per process (or per editing session) and pass it to every
    call: a unit whose items did not change is never solved again."""

    def __init__(self, max_entries: int = 100_000) -> None:
        self._data: LRUCache[str, object] = LRUCache(max_entries)
        self._lock = threading.Lock()
        self.max_entries = max_entries
        self.hits = 0
        self.misses = 0
        self._last: tuple[Orders, LogicModel] | None = None

    def model(self, orders: Orders) -> LogicModel:
        """The parsed model of these very orders (the same object) if the last call built it:
        check_logic and check_properties on one version of the orders parse it once."""
        with self._lock:
            last = self._last
        if last is not None and last[0] is orders:
            return last[1]
        model = LogicModel(orders)
        if last is not None:
            model.carry_goal_items(last[1])
        with self._lock:
            self._last = (orders, model)
        return model

    def get(self, key: str) -> object | None:
        with self._lock:
            value = self._data.get(key)
            if value is None:
                self.misses += 1
            else:
                self.hits += 1
            return value

    def holds(self, key: str, value: object) -> bool:
        """Whether `value` itself is the result kept under `key` (counted as the hit that
        `get` of it would be): a result carried from an earlier run is then the one a lookup
        by its key returns now."""
        with self._lock:
            if self._data.get(key) is not value:
                return False
            self.hits += 1
            return True

    def put(self, key: str, value: object) -> None:
        with self._lock:
            self._data[key] = value

    def __len__(self) -> int:
        return len(self._data)

    def clear(self) -> None:
        with self._lock:
            self._data.clear()
            self.hits = self.misses = 0
            self._last = None


_DIGEST = attrgetter("digest")
# A base's (digests, digest of them) by the base itself (a frozenset made once per run and
# quarantine).
_BASES: WeakKeyDictionary[frozenset[Item], tuple[frozenset[bytes], bytes]] = (
    WeakKeyDictionary())


def unit_key(kind: str, items: Iterable[Item], base: frozenset[Item] = frozenset()) -> str:
    """The digest of a unit's inputs: the digests of its items' sources, in a fixed order.
    With `base` (items every unit of a run holds), one digest of the base's stands for its
    items when they are all among the unit's (each listed once, as a unit's are): the
    hundreds of mission-wide constraints are sorted once, not once per goal. Membership is by
    digest, not by object: a model after an edit reuses the items of the one before (whose
    base is another set of the same statements), and the key must not change with that. The
    same set of items has the same key either way; its 37 bytes never read as whole 32-byte
    digests of a key made without one."""
    digests = list(map(_DIGEST, items))
    if base:
        members, _ = _base(base)
        own = [d for d in digests if d not in members]
        if len(digests) - len(own) == len(members):
            return _with_base(kind, own, base)
    digests.sort()
    return hashlib.sha256(_head(kind) + b"".join(digests)).hexdigest()


def unit_key_apart(kind: str, apart: Iterable[Item], base: frozenset[Item]) -> str:
    """`unit_key(kind, [*apart, *base], base)` for a caller that holds the unit's items but
    the base apart (none of them a statement of the base's): no scan of the base's hundreds
    of items to find them again."""
    if not base:
        return unit_key(kind, apart)
    return _with_base(kind, list(map(_DIGEST, apart)), base)


def _head(kind: str) -> bytes:
    return f"{VERSION}\x1e{kind}\x1e".encode()


def _with_base(kind: str, own: list[bytes], base: frozenset[Item]) -> str:
    own.sort()
    return hashlib.sha256(_head(kind) + b"base\x1e" + _base(base)[1]
                          + b"".join(own)).hexdigest()


def _base(base: frozenset[Item]) -> tuple[frozenset[bytes], bytes]:
    found = _BASES.get(base)
    if found is None:
        members = frozenset(map(_DIGEST, base))
        found = _BASES[base] = (members, hashlib.sha256(b"".join(sorted(members))).digest())
    return found
