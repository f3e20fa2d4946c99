"""Unit results cached by the digest of their items' sources."""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Iterable
from operator import attrgetter

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


def unit_key(kind: str, items: Iterable[Item]) -> str:
    """The digest of a unit's inputs: the digests of its items' sources, in a fixed order."""
    digests = sorted(map(_DIGEST, items))
    return hashlib.sha256(f"{VERSION}\x1e{kind}\x1e".encode() + b"".join(digests)).hexdigest()
