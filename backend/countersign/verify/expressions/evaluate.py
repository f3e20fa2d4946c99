"""Partial evaluation: what the facts of one goal (behaviour, area, area tags) already
decide."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction

from ...orders.expressions.tree import (
    Compare,
    Context,
    Expr,
    Implies,
    Logic,
    Name,
    Neg,
    Not,
    Num,
    Special,
    Sum,
    Text,
    Truth,
)


@dataclass(frozen=True)
class Facts:
    behavior: str | None
    area: str | None
    tags: frozenset[str]


class _Unknown:
    __slots__ = ()

    def __repr__(self) -> str:
        return "UNKNOWN"


UNKNOWN = _Unknown()
_NO_STRING = object()  # the behaviour or area of a goal that names none: equal to no text

_CMP: dict[str, Callable[[object, object], bool]] = {
    "==": lambda a, b: a == b,
    "!=": lambda a, b: a != b,
    "<": lambda a, b: a < b,  # type: ignore[operator]
    "<=": lambda a, b: a <= b,  # type: ignore[operator]
    ">": lambda a, b: a > b,  # type: ignore[operator]
    ">=": lambda a, b: a >= b,  # type: ignore[operator]
}


def fold(expr: Expr, facts: Facts) -> bool | None:
    """True or False when the goal's facts alone decide a (type-checked) condition, None
    when the answer depends on quantities."""
    value = _evaluate(expr, facts)
    return value if isinstance(value, bool) else None


def _evaluate(expr: Expr, facts: Facts) -> object:
    if isinstance(expr, Num):
        return expr.value
    if isinstance(expr, Text):
        return expr.value
    if isinstance(expr, Truth):
        return expr.value
    if isinstance(expr, Name):
        return UNKNOWN
    if isinstance(expr, Special):
        named = facts.behavior if expr.name == "behavior" else facts.area
        return _NO_STRING if named is None else named
    if isinstance(expr, Context):
        return expr.tag in facts.tags
    if isinstance(expr, Not):
        inner = _evaluate(expr.operand, facts)
        return UNKNOWN if inner is UNKNOWN else not inner
    if isinstance(expr, Neg):
        inner = _evaluate(expr.operand, facts)
        return UNKNOWN if inner is UNKNOWN else -inner  # type: ignore[operator]
    if isinstance(expr, Logic):
        decisive = expr.op == "or"
        unknown = False
        for operand in expr.operands:
            value = _evaluate(operand, facts)
            if value is UNKNOWN:
                unknown = True
            elif value is decisive:
                return decisive
        return UNKNOWN if unknown else not decisive
    if isinstance(expr, Implies):
        result: object = _evaluate(expr.operands[-1], facts)
        for operand in reversed(expr.operands[:-1]):
            premise = _evaluate(operand, facts)
            if premise is False or result is True:
                result = True
            elif premise is True:
                pass
            else:
                result = UNKNOWN
        return result
    if isinstance(expr, Compare):
        values = [_evaluate(operand, facts) for operand in expr.operands]
        unknown = False
        for index, op in enumerate(expr.ops):
            left, right = values[index], values[index + 1]
            if left is UNKNOWN or right is UNKNOWN:
                unknown = True
                continue
            if not _CMP[op](left, right):
                return False
        return UNKNOWN if unknown else True
    if isinstance(expr, Sum):
        total: Fraction = Fraction(0)
        for op, term in expr.terms:
            value = _evaluate(term, facts)
            if value is UNKNOWN:
                return UNKNOWN
            total = total + value if op == "+" else total - value  # type: ignore[operator]
        return total
    product: Fraction = Fraction(1)
    for op, factor in expr.factors:
        value = _evaluate(factor, facts)
        if value is UNKNOWN:
            return UNKNOWN
        if op == "/":
            if value == 0:
                return UNKNOWN
            product = product / value  # type: ignore[operator]
        else:
            product = product * value  # type: ignore[operator]
    return product
