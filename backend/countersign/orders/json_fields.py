"""Reading the fields of a JSON document into a typed contract (statement, envelope, report).

Here, beside the orders, because every layer reads such documents and the orders import nothing
of ours (approvals and verify both use it).

Each reader names the field it refuses by its path in the document (`predicate.version`), so a
malformed document is rejected with a message that says where, not with a KeyError."""

from __future__ import annotations

from typing import Any, TypeVar

T = TypeVar("T")

# What each JSON type is called in a message.
_NAMES = {str: "a string", int: "an integer", dict: "an object", list: "a list",
          bool: "true or false"}


class Malformed(ValueError):
    """A document without the shape its type requires; the message names the field."""


def an_object(data: Any, where: str) -> dict[str, Any]:
    if not isinstance(data, dict):
        raise Malformed(f"{where} must be an object")
    return data


def _is(value: Any, kind: type) -> bool:
    # JSON true/false are not integers here, though Python's bool is an int.
    return isinstance(value, kind) and not (kind is int and isinstance(value, bool))


def required(data: dict[str, Any], key: str, kind: type[T], where: str) -> T:
    """The field `key`, which must be present and of this JSON type."""
    if key not in data:
        raise Malformed(f"{where}.{key} is missing")
    value = data[key]
    if not _is(value, kind):
        raise Malformed(f"{where}.{key} must be {_NAMES[kind]}")
    return value  # type: ignore[no-any-return]


def nullable(data: dict[str, Any], key: str, kind: type[T], where: str) -> T | None:
    """The field `key`, which must be present, and null or of this JSON type."""
    if key not in data:
        raise Malformed(f"{where}.{key} is missing")
    return None if data[key] is None else required(data, key, kind, where)


def optional(data: dict[str, Any], key: str, kind: type[T], where: str) -> T | None:
    """The field `key`, which may be absent (None) but when present is of this JSON type:
    a field the writer omits rather than writing null, so absent and null stay apart."""
    return required(data, key, kind, where) if key in data else None


def only(data: dict[str, Any], known: tuple[str, ...], where: str) -> None:
    """Refuse a field the type does not know: it could not be written back, and what is
    signed must be understood whole."""
    unknown = sorted(set(data) - set(known))
    if unknown:
        raise Malformed(f"{where}.{unknown[0]} is not a field of this document")


def strings(value: dict[str, Any], where: str) -> dict[str, str]:
    """An object whose values are all strings (a digest map)."""
    for key, item in value.items():
        if not isinstance(item, str):
            raise Malformed(f"{where}.{key} must be a string")
    return value
