"""Canonical bytes and digest of orders (RFC 8785 JSON Canonicalization Scheme)."""

from __future__ import annotations

import hashlib
from typing import Any

import rfc8785

from .model import Orders


def orders_to_json(orders: Orders) -> dict[str, Any]:
    """The orders as plain JSON data, without defaults the author did not write."""
    data: dict[str, Any] = orders.model_dump(mode="json", exclude_unset=True)
    data["format"] = orders.format
    return data


def canonical_bytes(orders: Orders) -> bytes:
    return bytes(rfc8785.dumps(orders_to_json(orders)))


def digest(orders: Orders) -> str:
    return "sha256:" + hashlib.sha256(canonical_bytes(orders)).hexdigest()
