"""Canonical bytes and digest of orders (RFC 8785 JSON Canonicalization Scheme).

An edit changes one goal of many, and the canonical form of a thousand goals took longer than
validating the edit: each goal's canonical bytes are kept, by the goal's JSON as written, and
the orders' bytes are assembled around them. RFC 8785 writes an object as its members sorted
by the UTF-16 code units of their names, `"name":value` joined by commas, and an array as its
elements joined by commas, with no white space: the assembled bytes are the bytes of the whole
(tests compare both on random orders)."""

from __future__ import annotations

import hashlib
import json
import threading
from collections.abc import Sequence
from typing import Any

import rfc8785
from cachetools import LRUCache

from .model import Orders

# Bytes of canonical goals kept (a 1,000-goal mission holds about half a megabyte).
GOAL_BYTES_KEPT = 32 * 2**20

_goals: LRUCache[str, bytes] = LRUCache(GOAL_BYTES_KEPT, getsizeof=len)
_goals_lock = threading.Lock()


def orders_to_json(orders: Orders) -> dict[str, Any]:
    """The orders as plain JSON data, without defaults the author did not write."""
    data: dict[str, Any] = orders.model_dump(mode="json", exclude_unset=True)
    data["format"] = orders.format
    return data


def goal_texts(data: dict[str, Any]) -> list[str]:
    """The JSON text of each goal of orders made JSON data by orders_to_json: what the goals'
    canonical bytes (and verify.parts' keys) are kept by, made once for both."""
    goals = data.get("goals")
    if not isinstance(goals, list):
        return []
    return [json.dumps(goal, ensure_ascii=False) for goal in goals]


def _goal_bytes(goal: Any, key: str) -> bytes:
    # The goal's JSON text is the key: equal texts are equal data (the text keeps 1 and 1.0
    # apart; member order only makes two keys for one canonical form).
    with _goals_lock:
        found = _goals.get(key)
    if found is None:
        found = bytes(rfc8785.dumps(goal))
        with _goals_lock:
            _goals[key] = found
    return found


def canonical_bytes(orders: Orders) -> bytes:
    return canonical_bytes_of_json(orders_to_json(orders))


def canonical_bytes_of_json(data: dict[str, Any], texts: Sequence[str] | None = None) -> bytes:
    """The canonical bytes of orders already made JSON data by orders_to_json (a caller that
    stores that data too makes it once); `data` is only read. `texts`: goal_texts(data), when
    the caller made them already."""
    goals = data.get("goals")
    if not isinstance(goals, list) or not goals:
        return bytes(rfc8785.dumps(data))
    if texts is None:
        texts = goal_texts(data)
    members = []
    for name in sorted(data, key=lambda k: k.encode("utf-16be")):
        value = (b"[" + b",".join(map(_goal_bytes, goals, texts)) + b"]" if name == "goals"
                 else bytes(rfc8785.dumps(data[name])))
        members.append(bytes(rfc8785.dumps(name)) + b":" + value)
    return b"{" + b",".join(members) + b"}"


def digest(orders: Orders) -> str:
    return digest_of_json(orders_to_json(orders))


def digest_of_json(data: dict[str, Any], texts: Sequence[str] | None = None) -> str:
    """digest() of orders already made JSON data by orders_to_json (`texts` as for
    canonical_bytes_of_json)."""
    return "sha256:" + hashlib.sha256(canonical_bytes_of_json(data, texts)).hexdigest()
