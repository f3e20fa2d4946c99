"""Conditions as formulas of linear comparisons, with a goal's facts put in (bounds.py).

A type-checked condition becomes True, False or a formula: ("a", terms, constant, op) meaning
sum(c * x) + constant op 0 with op one of "<=", "<", "=", "!=" (terms: sorted (name,
coefficient) pairs), ("b", name, value) for a Boolean quantity or a tag with no fact, ("s",
("str", "behavior" | "area"), text, equal) for a behaviour or area with no fact, ("&", parts)
and ("|", parts); negation is pushed down to the comparisons. Numbers are exact (an int where
integral). What is not linear (a product of quantities, a division by a quantity or by 0,
which SMT-LIB leaves unspecified) raises Unsupported.
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any, Literal

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
    Product,
    Special,
    Sum,
    Text,
    Truth,
)

Formula = Any
Facts = dict[Any, Any]
Number = int | Fraction  # ints where integral: exact, and far cheaper to add and compare
_MISSING = object()


class Unsupported(Exception):
    """A statement bounds.py does not decide (z3 does)."""


class Translate:
    """A type-checked condition under the goal's facts, as a Formula (negation pushed to the
    comparisons)."""

    def __init__(self, kinds: Mapping[str, str], facts: Facts) -> None:
        self.kinds = kinds
        self.facts = facts

    def condition(self, e: Expr, positive: bool) -> Formula:
        if isinstance(e, Truth):
            return e.value == positive
        if isinstance(e, Context):
            holds = self.facts.get(("ctx", e.tag), _MISSING)
            if holds is _MISSING:  # no fact (a subset of a unit): free, like z3's constant
                return ("b", ("ctx", e.tag), positive)
            return holds == positive
        if isinstance(e, Name):
            if self.kinds.get(e.name) != "boolean":
                raise Unsupported
            return ("b", e.name, positive)
        if isinstance(e, Not):
            return self.condition(e.operand, not positive)
        if isinstance(e, Logic):
            conjunction = (e.op == "and") == positive
            return join("&" if conjunction else "|",
                         [self.condition(o, positive) for o in e.operands])
        if isinstance(e, Implies):
            # a => (b => c) is (not a) or (not b) or c.
            parts = [self.condition(o, not positive) for o in e.operands[:-1]]
            parts.append(self.condition(e.operands[-1], positive))
            return join("|" if positive else "&", parts)
        if isinstance(e, Compare):
            atoms = [self._compare(e.operands[i], op, e.operands[i + 1], positive)
                     for i, op in enumerate(e.ops)]
            return join("&" if positive else "|", atoms)
        raise Unsupported

    def _compare(self, left: Expr, op: str, right: Expr, positive: bool) -> Formula:
        if isinstance(left, (Special, Text)) or isinstance(right, (Special, Text)):
            if op not in {"==", "!="}:
                raise Unsupported
            equal = (op == "==") == positive
            a, b = self._string(left), self._string(right)
            if a is _MISSING and isinstance(right, Text):
                return ("s", ("str", left.name), b, equal)  # type: ignore[union-attr]
            if b is _MISSING and isinstance(left, Text):
                return ("s", ("str", right.name), a, equal)  # type: ignore[union-attr]
            if a is _MISSING or b is _MISSING:
                raise Unsupported
            return (a == b) == equal
        terms, constant = _minus(self._linear(left), self._linear(right))
        if not positive:
            op = {"<=": ">", "<": ">=", ">=": "<", ">": "<=", "==": "!=", "!=": "=="}[op]
        if op in {">=", ">"}:  # a >= b is b - a <= 0
            terms = {n: -c for n, c in terms.items()}
            constant = -constant
            op = "<=" if op == ">=" else "<"
        op = {"==": "=", "!=": "!="}.get(op, op)
        terms = {n: c for n, c in terms.items() if c}
        if not terms:
            return compare_constant(constant, op)
        return ("a", tuple(sorted((n, exact(c)) for n, c in terms.items())), exact(constant),
                op)

    def _string(self, e: Expr) -> Any:
        if isinstance(e, Text):
            return e.value
        if isinstance(e, Special):
            return self.facts.get(e.name, _MISSING)
        raise Unsupported

    def _linear(self, e: Expr) -> tuple[dict[str, Fraction], Fraction]:
        if isinstance(e, Num):
            return {}, Fraction(e.value)
        if isinstance(e, Name):
            if self.kinds.get(e.name) == "boolean":
                raise Unsupported
            return {e.name: Fraction(1)}, Fraction(0)
        if isinstance(e, Neg):
            terms, constant = self._linear(e.operand)
            return {n: -c for n, c in terms.items()}, -constant
        if isinstance(e, Sum):
            total: tuple[dict[str, Fraction], Fraction] = ({}, Fraction(0))
            for op, term in e.terms:
                value = self._linear(term)
                total = _minus(total, value) if op == "-" else _minus(total, _scale(value, -1))
            return total
        if isinstance(e, Product):
            acc = self._linear(e.factors[0][1])
            for op, factor in e.factors[1:]:
                value = self._linear(factor)
                if value[0] and (op == "/" or acc[0]):
                    raise Unsupported  # not linear (z3 decides)
                if op == "/":
                    if value[1] == 0:
                        raise Unsupported  # SMT-LIB leaves x / 0 unspecified
                    acc = _scale(acc, 1 / value[1])
                else:
                    acc = _scale(value, acc[1]) if not acc[0] else _scale(acc, value[1])
            return acc
        raise Unsupported


def _scale(value: tuple[dict[str, Fraction], Fraction], k: Fraction | int) -> tuple[
    dict[str, Fraction], Fraction
]:
    return {n: c * k for n, c in value[0].items()}, value[1] * k


def _minus(a: tuple[dict[str, Fraction], Fraction], b: tuple[dict[str, Fraction], Fraction]
           ) -> tuple[dict[str, Fraction], Fraction]:
    terms = dict(a[0])
    for n, c in b[0].items():
        terms[n] = terms.get(n, Fraction(0)) - c
    return terms, a[1] - b[1]


def exact(value: Any) -> Any:
    """A Fraction as an int when integral (None stays None)."""
    if isinstance(value, Fraction) and value.denominator == 1:
        return value.numerator
    return value


def compare_constant(value: Number, op: str) -> bool:
    return {"<=": value <= 0, "<": value < 0, "=": value == 0, "!=": value != 0}[op]


def join(op: Literal["&", "|"], parts: list[Formula]) -> Formula:
    decisive = op == "|"
    out: list[Formula] = []
    for part in parts:
        if part is decisive:
            return decisive
        if part is not (not decisive):
            out.extend(part[1] if isinstance(part, tuple) and part[0] == op else (part,))
    if not out:
        return not decisive
    return out[0] if len(out) == 1 else (op, tuple(out))
