"""The one JSON policy of every reader and request body.

Python's `json` accepts what RFC 8259 does not: `NaN`, `Infinity`, numbers such as `1e999` that
overflow to infinity, and the same key twice in one object (the last one silently wins). Each of
these has cost a 500 or a silently wrong value somewhere, so every JSON the application reads
from outside goes through `loads`, which refuses them with the JSON path of the value, and also
bounds nesting depth (the C parser's own limit is the interpreter's recursion limit).
"""

from __future__ import annotations

import json
import math
from typing import Any

# Orders nest about six levels (orders > goals > goal > envelope > quantity > bound); request
# bodies fewer. 64 leaves room for free-form `params` without letting a body recurse deeply.
MAX_DEPTH = 64
# RFC 8785 (the canonical form orders are digested in) refuses integers a double cannot hold
# exactly; orders are checked for them (`check(..., exact_integers=True)`), request bodies not.
MAX_EXACT_INTEGER = 2**53 - 1


class JsonPolicyError(ValueError):
    """JSON that parses but breaks the policy (or does not parse); `path` says where."""

    def __init__(self, path: str, message: str) -> None:
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}")


class _DuplicateKey(ValueError):
    def __init__(self, key: str) -> None:
        self.key = key
        super().__init__(key)


def _pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    # The dict is built in C; only an object with a repeated key is walked here.
    result = dict(pairs)
    if len(result) != len(pairs):
        seen: set[str] = set()
        for key, _ in pairs:
            if key in seen:
                raise _DuplicateKey(key)
            seen.add(key)
    return result


def _key_path(path: str, key: str) -> str:
    if key.replace("_", "").isalnum():
        return f"{path}.{key}"
    return f"{path}[{json.dumps(key)}]"


def _breaks(item: Any, exact_integers: bool) -> bool:
    """Whether a number breaks the policy (anything else is judged by the walks)."""
    if isinstance(item, float):
        return not math.isfinite(item)
    return (exact_integers and isinstance(item, int) and not isinstance(item, bool)
            and abs(item) > MAX_EXACT_INTEGER)


def _nested_within(value: Any, max_depth: int) -> bool:
    """Whether no container in `value` lies `max_depth` or more levels deep."""
    stack: list[tuple[Any, int]] = [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if depth >= max_depth:
            return False
        below = depth + 1
        for child in item.values() if type(item) is dict else item:
            kind = type(child)
            if kind is dict or kind is list:
                stack.append((child, below))
    return True


def _conforms(value: Any, max_depth: int, exact_integers: bool) -> bool:
    """Whether `value` keeps the policy, walked without the paths that only an error needs
    (a 1,000-goal body has some 130,000 keys and items: building each one's path string cost
    more than parsing it)."""
    stack: list[tuple[Any, int]] = [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            values: Any = item.values()
        elif isinstance(item, list):
            values = item
        elif _breaks(item, exact_integers):
            return False
        else:
            continue
        if depth >= max_depth:
            return False
        for child in values:
            if isinstance(child, (dict, list)):
                stack.append((child, depth + 1))
            elif isinstance(child, (float, int)) and _breaks(child, exact_integers):
                return False
    return True


def check(value: Any, max_depth: int = MAX_DEPTH, exact_integers: bool = False) -> None:
    """Raise `JsonPolicyError` for the first non-finite number or too-deep value (and, with
    `exact_integers`, integer beyond ±(2**53 - 1)), by path.

    Iterative, so that its own depth is not limited by the interpreter's recursion limit.
    Values that keep the policy (nearly all) are walked once without paths; only a value that
    breaks it is walked again to say where."""
    if _conforms(value, max_depth, exact_integers):
        return
    stack: list[tuple[Any, str, int]] = [(value, "$", 0)]
    while stack:
        item, path, depth = stack.pop()
        if isinstance(item, float):
            if not math.isfinite(item):
                raise JsonPolicyError(
                    path, "numbers must be finite (NaN, Infinity and values beyond "
                    "±1.8e308 such as 1e999 are not accepted)")
        elif (exact_integers and isinstance(item, int) and not isinstance(item, bool)
              and abs(item) > MAX_EXACT_INTEGER):
            raise JsonPolicyError(
                path, f"integers must lie within ±{MAX_EXACT_INTEGER} (write larger values "
                "as decimals, e.g. 1.5e20)")
        elif isinstance(item, (dict, list)):
            if depth >= max_depth:
                raise JsonPolicyError(path, f"JSON nested deeper than {max_depth} levels")
            if isinstance(item, dict):
                children = [(v, _key_path(path, str(k)), depth + 1) for k, v in item.items()]
            else:
                children = [(v, f"{path}[{i}]", depth + 1) for i, v in enumerate(item)]
            stack.extend(reversed(children))


def loads(text: str | bytes, max_depth: int = MAX_DEPTH) -> Any:
    """Parse `text` under the policy, or raise `JsonPolicyError` saying what and where."""
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise JsonPolicyError("$", f"not UTF-8 text (byte {exc.start})") from None
    # Every number that can be non-finite passes here (NaN, Infinity, 1e999: a fraction or
    # an exponent); kept as floats so that the walk in `check` reports them with their path.
    nonfinite: list[float] = []

    def number(written: str) -> float:
        value = float(written)
        if not math.isfinite(value):
            nonfinite.append(value)
        return value

    try:
        parsed = json.loads(text, object_pairs_hook=_pairs, parse_constant=number,
                            parse_float=number)
    except json.JSONDecodeError as exc:
        raise JsonPolicyError(
            "$", f"invalid JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    except _DuplicateKey as exc:
        raise JsonPolicyError("$", f"the key {exc.key!r} appears twice in one object") from None
    except RecursionError:
        raise JsonPolicyError("$", "JSON nested too deeply") from None
    except ValueError as exc:  # e.g. an integer with more digits than int() converts
        raise JsonPolicyError("$", f"invalid JSON: {exc}") from None
    # Nearly every body keeps the policy: then only the depth is left to walk, containers only.
    if nonfinite or (isinstance(parsed, (dict, list)) and not _nested_within(parsed, max_depth)):
        check(parsed, max_depth)
    return parsed
