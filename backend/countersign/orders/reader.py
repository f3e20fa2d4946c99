"""Read orders from bytes or files: JSON (`countersign.orders/1`), AVCL XML or MEO Turtle.

Malformed input raises `OrdersReadError` carrying a list of problems, each with a JSON path
(`$.goals[2].next.succeed`) and a message; callers never see a stack trace.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from .. import strict_json
from ..limits import MAX_INPUT_BYTES, MIB
from .findings import Finding
from .model import Orders

MAX_PROBLEMS_SHOWN = 20


@dataclass(frozen=True)
class Problem:
    path: str
    message: str

    def __str__(self) -> str:
        return f"{self.path}: {self.message}"


class OrdersReadError(Exception):
    """Input that cannot be read as orders; `problems` says what and where."""

    def __init__(self, problems: list[Problem], total: int | None = None) -> None:
        self.problems = problems
        self.total = len(problems) if total is None else total
        super().__init__(self.summary())

    def summary(self) -> str:
        lines = [str(p) for p in self.problems]
        if self.total > len(self.problems):
            lines.append(f"... and {self.total - len(self.problems)} more problems")
        return "\n".join(lines)


@dataclass(frozen=True)
class ReadResult:
    orders: Orders
    # Findings the reader itself made, e.g. SINK warnings for NPS default handlers.
    findings: list[Finding] = field(default_factory=list)
    source_format: str = "json"


def _json_path(loc: tuple[int | str, ...]) -> str:
    path = "$"
    for part in loc:
        if isinstance(part, int):
            path += f"[{part}]"
        elif part.replace("_", "").isalnum():
            path += f".{part}"
        else:
            path += f"[{json.dumps(part)}]"
    return path


def location_path(loc: tuple[int | str, ...]) -> str:
    """The JSON path (`$.goals[0].next`) of a pydantic error location, without its tags."""
    return _json_path(_model_path(loc))


def _model_path(loc: tuple[int | str, ...]) -> tuple[int | str, ...]:
    # Pydantic adds union branch and validator tags (`str`, `list[str]`, `function-after[...]`)
    # that mean nothing to an author; keep field names and indices only.
    return tuple(
        part
        for part in loc
        if isinstance(part, int)
        or not (
            part in {"str", "list[str]", "none", "literal['mission']", "list[constrained-str]"}
            or "[" in part
            or part.startswith("function-")
        )
    )


def problems_from_validation(exc: ValidationError) -> OrdersReadError:
    problems: list[Problem] = []
    seen: set[tuple[str, str]] = set()
    errors = exc.errors(include_url=False)
    for err in errors:
        path = location_path(tuple(err["loc"]))
        message = str(err["msg"]).removeprefix("Value error, ")
        if err["type"] == "literal_error" and path == "$.format":
            message = "format must be 'countersign.orders/1'"
        if (path, message) in seen:
            continue
        seen.add((path, message))
        problems.append(Problem(path, message))
    return OrdersReadError(problems[:MAX_PROBLEMS_SHOWN], total=len(problems))


def reject_duplicate_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    result: dict[str, Any] = {}
    for key, value in pairs:
        if key in result:
            raise ValueError(f"the key {key!r} appears twice in one object")
        result[key] = value
    return result


def orders_from_data(data: Any) -> Orders:
    if not isinstance(data, dict):
        kind = "an array" if isinstance(data, list) else f"a {type(data).__name__}"
        raise OrdersReadError([Problem("$", f"orders must be a JSON object, not {kind}")])
    try:
        return Orders.model_validate(data)
    except ValidationError as exc:
        raise problems_from_validation(exc) from None


def read_json(data: bytes) -> Orders:
    # One JSON policy everywhere (strict_json): no duplicate keys, no NaN/Infinity/1e999,
    # bounded depth; each refusal names its JSON path.
    try:
        parsed = strict_json.loads(data)
    except strict_json.JsonPolicyError as exc:
        raise OrdersReadError([Problem(exc.path, exc.message)]) from None
    return orders_from_data(parsed)


# Turtle that opens with a triple: an IRI with a scheme, fragment or nothing in it (not an XML
# tag), a blank node, or an anonymous node, followed by a predicate.
_PREDICATE = rb"(?:<|a\s|[A-Za-z_][\w.-]*:)"
_TURTLE_TRIPLE = re.compile(
    rb"(?:<(?:[^\s<>\"{}|^`\\]*[:#][^\s<>\"{}|^`\\]*)?>|_:\S+|\[\s*\]|\[)\s*" + _PREDICATE
)


def sniff_format(data: bytes) -> str:
    """json, avcl (XML) or turtle, from the first bytes."""
    text = data.lstrip(b"\xef\xbb\xbf \t\r\n")
    head = text[:1]
    lowered = text[:6].lower()
    if head in (b"@", b"#") or lowered.startswith((b"prefix", b"base")):
        return "turtle"
    if head in (b"<", b"[", b"_") and _TURTLE_TRIPLE.match(text):
        return "turtle"
    if head in (b"{", b"["):
        return "json"
    if head == b"<":
        return "avcl"
    return "json"


def read_bytes(data: bytes, name: str = "<input>") -> ReadResult:
    """Read orders from raw bytes, detecting JSON, AVCL XML or MEO Turtle by content."""
    if len(data) > MAX_INPUT_BYTES:
        limit_mib = MAX_INPUT_BYTES // MIB
        raise OrdersReadError([Problem("$", f"{name} is larger than the {limit_mib} MiB limit")])
    if not data.strip():
        raise OrdersReadError([Problem("$", f"{name} is empty")])
    kind = sniff_format(data)
    if kind == "avcl":
        from .avcl import read_avcl

        return read_avcl(data, name)
    if kind == "turtle":
        from .turtle import read_turtle

        return read_turtle(data, name)
    return ReadResult(read_json(data), [], "json")


def read_file(path: str | Path) -> ReadResult:
    """Read orders from a file, never reading more than the size limit."""
    file_path = Path(path)
    try:
        with file_path.open("rb") as handle:
            data = handle.read(MAX_INPUT_BYTES + 1)
    except FileNotFoundError:
        raise OrdersReadError([Problem("$", f"{file_path} does not exist")]) from None
    except IsADirectoryError:
        raise OrdersReadError([Problem("$", f"{file_path} is a directory")]) from None
    except OSError as exc:
        raise OrdersReadError([Problem("$", f"cannot read {file_path}: {exc.strerror}")]) from None
    return read_bytes(data, str(file_path))
