"""Read orders from bytes or files: JSON (`countersign.orders/1`), AVCL XML or MEO Turtle.

Malformed input raises `OrdersReadError` carrying a list of problems, each with a JSON path
(`$.goals[2].next.succeed`) and a message; callers never see a stack trace.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError
from pydantic_core import ErrorDetails

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


# The reader core, shared by every JSON input read into a pydantic model (orders, and the
# planning problem in plan/model.py): the error class and the wording of a few errors differ.
ReadError = TypeVar("ReadError", bound=OrdersReadError)
Model = TypeVar("Model", bound=BaseModel)
# (pydantic's error, its JSON path, its message) -> the (path, message) an author reads.
Reword = Callable[[ErrorDetails, str, str], tuple[str, str]]


def validation_problems(exc: ValidationError, error: type[ReadError],
                        reword: Reword) -> ReadError:
    """One problem per distinct (path, message) of a validation error, the first
    MAX_PROBLEMS_SHOWN of them shown."""
    problems: list[Problem] = []
    seen: set[tuple[str, str]] = set()
    for err in exc.errors(include_url=False):
        path = location_path(tuple(err["loc"]))
        message = str(err["msg"]).removeprefix("Value error, ")
        path, message = reword(err, path, message)
        if (path, message) in seen:
            continue
        seen.add((path, message))
        problems.append(Problem(path, message))
    return error(problems[:MAX_PROBLEMS_SHOWN], total=len(problems))


def validated(model: type[Model], data: Any, *, what: str, error: type[ReadError],
              reword: Reword) -> Model:
    """`data` (parsed JSON) as `model`, or `error` saying what is wrong and where."""
    if not isinstance(data, dict):
        kind = "an array" if isinstance(data, list) else f"a {type(data).__name__}"
        raise error([Problem("$", f"{what} must be a JSON object, not {kind}")])
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        raise validation_problems(exc, error, reword) from None


def refuse_size(data: bytes, name: str, error: type[OrdersReadError]) -> None:
    """Refuse input over the size limit, or empty."""
    if len(data) > MAX_INPUT_BYTES:
        limit_mib = MAX_INPUT_BYTES // MIB
        raise error([Problem("$", f"{name} is larger than the {limit_mib} MiB limit")])
    if not data.strip():
        raise error([Problem("$", f"{name} is empty")])


def json_data(data: bytes, error: type[OrdersReadError]) -> Any:
    # One JSON policy everywhere (strict_json): no duplicate keys, no NaN/Infinity/1e999,
    # bounded depth; each refusal names its JSON path.
    try:
        return strict_json.loads(data)
    except strict_json.JsonPolicyError as exc:
        raise error([Problem(exc.path, exc.message)]) from None


def read_limited(path: str | Path, error: type[OrdersReadError]) -> bytes:
    """A file's bytes, never more than one byte over the size limit."""
    file_path = Path(path)
    try:
        with file_path.open("rb") as handle:
            return handle.read(MAX_INPUT_BYTES + 1)
    except FileNotFoundError:
        raise error([Problem("$", f"{file_path} does not exist")]) from None
    except IsADirectoryError:
        raise error([Problem("$", f"{file_path} is a directory")]) from None
    except OSError as exc:
        raise error([Problem("$", f"cannot read {file_path}: {exc.strerror}")]) from None


def _reword_orders(err: ErrorDetails, path: str, message: str) -> tuple[str, str]:
    if err["type"] == "literal_error" and path == "$.format":
        message = "format must be 'countersign.orders/1'"
    return path, message


def problems_from_validation(exc: ValidationError) -> OrdersReadError:
    return validation_problems(exc, OrdersReadError, _reword_orders)


def orders_from_data(data: Any) -> Orders:
    return validated(Orders, data, what="orders", error=OrdersReadError, reword=_reword_orders)


def read_json(data: bytes) -> Orders:
    return orders_from_data(json_data(data, OrdersReadError))


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
    refuse_size(data, name, OrdersReadError)
    kind = sniff_format(data)
    if kind == "avcl":
        from .avcl import read_avcl

        return read_avcl(data, name)
    if kind == "turtle":
        from .turtle import read_turtle

        return read_turtle(data, name)
    return ReadResult(read_json(data), [])


def read_file(path: str | Path) -> ReadResult:
    """Read orders from a file, never reading more than the size limit."""
    return read_bytes(read_limited(path, OrdersReadError), str(Path(path)))
