"""The orders' IRIs as plain strings, and the id helpers that read them, without rdflib.

`orders.turtle.vocabulary` builds rdflib terms from these; the MEO rules that `validate` checks
directly (`verify.meo.direct`) only compare and sort IRIs, so they use the strings and a
validation does not import rdflib (about a tenth of `countersign validate`'s start-up).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Any, Final, TypeVar

MISSION_BASE: Final = "https://countersign.example/mission/"


def mission_iri(mission_id: str) -> str:
    return MISSION_BASE + mission_id


def element_iri(mission_id: str, kind: str, element_id: str) -> str:
    return f"{MISSION_BASE}{mission_id}/{kind}#{element_id}"


def local_id(node: object) -> str:
    """The element id an IRI names: the part after '#', else after the last '/'."""
    text = str(node)
    if "#" in text:
        return text.rsplit("#", 1)[1]
    return text.rstrip("/").rsplit("/", 1)[-1]


_T = TypeVar("_T")


def first_by_id(items: Iterable[_T]) -> list[_T]:
    """The first element of each id (a DUP finding reports the others)."""
    seen: set[str] = set()
    result: list[_T] = []
    for item in items:
        item_id = getattr(item, "id", None)
        if isinstance(item_id, str) and item_id not in seen:
            seen.add(item_id)
            result.append(item)
    return result


_NATURAL: Final = re.compile(r"(\d+)")


def natural_key(text: str) -> tuple[Any, ...]:
    return tuple(int(part) if part.isdigit() else part for part in _NATURAL.split(text))
