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
from ...orders.expressions.visit import ExprVisitor

Formula = Any
Facts = dict[Any, Any]
Number = int | Fraction  # ints where integral: exact, and far cheaper to add and compare
Linear = tuple[dict[str, Fraction], Fraction]  # sum(c * x) + constant
_MISSING = object()


class Unsupported(Exception):
    """A statement bounds.py does not decide (z3 does)."""


class Translate:
    """A type-checked condition under the goal's facts, as a Formula (negation pushed to the
    comparisons)."""

    def __init__(self, kinds: Mapping[str, str], facts: Facts) -> None:
        self.kinds = kinds
        self.facts = facts
        self._linear = _Linear(kinds)
        self._strings = _Strings(facts)
        # One visitor per polarity, each the other's negation: `not` swaps them.
        self._positive = _Condition(self, True)
        self._negative = _Condition(self, False)

    def condition(self, e: Expr, positive: bool) -> Formula:
        return (self._positive if positive else self._negative).visit(e)

    def compare(self, left: Expr, op: str, right: Expr, positive: bool) -> Formula:
        a, b = self._strings.visit(left), self._strings.visit(right)
        if a is not None or b is not None:  # a text, a behaviour or an area
            if op not in {"==", "!="} or a is None or b is None:
                raise Unsupported
            equal = (op == "==") == positive
            if a[1] is _MISSING and b[0] == "text":
                return ("s", ("str", a[0]), b[1], equal)
            if b[1] is _MISSING and a[0] == "text":
                return ("s", ("str", b[0]), a[1], equal)
            if a[1] is _MISSING or b[1] is _MISSING:
                raise Unsupported
            return (a[1] == b[1]) == equal
        terms, constant = _minus(self._linear.visit(left), self._linear.visit(right))
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


class _Condition(ExprVisitor[Formula]):
    """A condition as a Formula, stated (positive) or negated; what is not a condition (a
    number, a text, a sum) is Unsupported, as the type checker never lets one stand here."""

    def __init__(self, translate: Translate, positive: bool) -> None:
        self.translate = translate
        self.positive = positive

    def _other(self) -> _Condition:
        t = self.translate
        return t._negative if self.positive else t._positive

    def visit_truth(self, node: Truth) -> Formula:
        return node.value == self.positive

    def visit_context(self, node: Context) -> Formula:
        holds = self.translate.facts.get(("ctx", node.tag), _MISSING)
        if holds is _MISSING:  # no fact (a subset of a unit): free, like z3's constant
            return ("b", ("ctx", node.tag), self.positive)
        return holds == self.positive

    def visit_name(self, node: Name) -> Formula:
        if self.translate.kinds.get(node.name) != "boolean":
            raise Unsupported
        return ("b", node.name, self.positive)

    def visit_not(self, node: Not) -> Formula:
        return self._other().visit(node.operand)

    def visit_logic(self, node: Logic) -> Formula:
        conjunction = (node.op == "and") == self.positive
        return join("&" if conjunction else "|", [self.visit(o) for o in node.operands])

    def visit_implies(self, node: Implies) -> Formula:
        # a => (b => c) is (not a) or (not b) or c.
        parts = [self._other().visit(o) for o in node.operands[:-1]]
        parts.append(self.visit(node.operands[-1]))
        return join("|" if self.positive else "&", parts)

    def visit_compare(self, node: Compare) -> Formula:
        atoms = [self.translate.compare(node.operands[i], op, node.operands[i + 1],
                                        self.positive)
                 for i, op in enumerate(node.ops)]
        return join("&" if self.positive else "|", atoms)

    def visit_num(self, node: Num) -> Formula:
        raise Unsupported

    def visit_text(self, node: Text) -> Formula:
        raise Unsupported

    def visit_special(self, node: Special) -> Formula:
        raise Unsupported

    def visit_neg(self, node: Neg) -> Formula:
        raise Unsupported

    def visit_sum(self, node: Sum) -> Formula:
        raise Unsupported

    def visit_product(self, node: Product) -> Formula:
        raise Unsupported


class _Strings(ExprVisitor[tuple[Any, Any] | None]):
    """A string operand as ("text", its value) or (behavior | area, the goal's fact, or
    _MISSING when it has none); None for what is not a string (a number, a condition)."""

    def __init__(self, facts: Facts) -> None:
        self.facts = facts

    def visit_text(self, node: Text) -> tuple[Any, Any] | None:
        return ("text", node.value)

    def visit_special(self, node: Special) -> tuple[Any, Any] | None:
        return (node.name, self.facts.get(node.name, _MISSING))

    def _none(self, node: Expr) -> tuple[Any, Any] | None:
        return None

    visit_num = visit_truth = visit_name = visit_context = _none
    visit_neg = visit_not = visit_sum = visit_product = _none
    visit_compare = visit_logic = visit_implies = _none


class _Linear(ExprVisitor[Linear]):
    """An arithmetic term as sum(c * x) + constant; a product of quantities, a division by a
    quantity or by 0 (which SMT-LIB leaves unspecified) and a Boolean are Unsupported."""

    def __init__(self, kinds: Mapping[str, str]) -> None:
        self.kinds = kinds

    def visit_num(self, node: Num) -> Linear:
        return {}, Fraction(node.value)

    def visit_name(self, node: Name) -> Linear:
        if self.kinds.get(node.name) == "boolean":
            raise Unsupported
        return {node.name: Fraction(1)}, Fraction(0)

    def visit_neg(self, node: Neg) -> Linear:
        terms, constant = self.visit(node.operand)
        return {n: -c for n, c in terms.items()}, -constant

    def visit_sum(self, node: Sum) -> Linear:
        total: Linear = ({}, Fraction(0))
        for op, term in node.terms:
            value = self.visit(term)
            total = _minus(total, value) if op == "-" else _minus(total, _scale(value, -1))
        return total

    def visit_product(self, node: Product) -> Linear:
        acc = self.visit(node.factors[0][1])
        for op, factor in node.factors[1:]:
            value = self.visit(factor)
            if value[0] and (op == "/" or acc[0]):
                raise Unsupported  # not linear (z3 decides)
            if op == "/":
                if value[1] == 0:
                    raise Unsupported  # SMT-LIB leaves x / 0 unspecified
                acc = _scale(acc, 1 / value[1])
            else:
                acc = _scale(value, acc[1]) if not acc[0] else _scale(acc, value[1])
        return acc

    def _unsupported(self, node: Expr) -> Linear:
        raise Unsupported

    visit_text = visit_truth = visit_special = visit_context = _unsupported
    visit_not = visit_compare = visit_logic = visit_implies = _unsupported


def _scale(value: Linear, k: Fraction | int) -> Linear:
    return {n: c * k for n, c in value[0].items()}, value[1] * k


def _minus(a: Linear, b: Linear) -> Linear:
    terms = dict(a[0])
    for n, c in b[0].items():
        terms[n] = terms.get(n, Fraction(0)) - c
    return terms, a[1] - b[1]


def exact(value: Any) -> Any:
    """A Fraction as an int when integral (None stays None)."""
    # `type`, not isinstance: Fraction's abstract base makes isinstance a slow Python call.
    if type(value) is Fraction and value.denominator == 1:
        return value.numerator
    return value


def compare_constant(value: Number, op: str) -> bool:
    if op == "<=":
        return value <= 0
    if op == "<":
        return value < 0
    if op == "=":
        return value == 0
    if op == "!=":
        return value != 0
    raise KeyError(op)


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
