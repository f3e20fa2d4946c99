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
    Product,
    Special,
    Sum,
    Text,
    Truth,
)
from ...orders.expressions.visit import ExprVisitor


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
    value = _Evaluate(facts).visit(expr)
    return value if isinstance(value, bool) else None


class _Evaluate(ExprVisitor[object]):
    """The value of a node (a Fraction, text, a bool, _NO_STRING) or UNKNOWN."""

    __slots__ = ("facts",)

    def __init__(self, facts: Facts) -> None:
        self.facts = facts

    def visit_num(self, node: Num) -> object:
        return node.value

    def visit_text(self, node: Text) -> object:
        return node.value

    def visit_truth(self, node: Truth) -> object:
        return node.value

    def visit_name(self, node: Name) -> object:
        return UNKNOWN

    def visit_special(self, node: Special) -> object:
        named = self.facts.behavior if node.name == "behavior" else self.facts.area
        return _NO_STRING if named is None else named

    def visit_context(self, node: Context) -> object:
        return node.tag in self.facts.tags

    def visit_not(self, node: Not) -> object:
        inner = self.visit(node.operand)
        return UNKNOWN if inner is UNKNOWN else not inner

    def visit_neg(self, node: Neg) -> object:
        inner = self.visit(node.operand)
        return UNKNOWN if inner is UNKNOWN else -inner  # type: ignore[operator]

    def visit_logic(self, node: Logic) -> object:
        decisive = node.op == "or"
        unknown = False
        for operand in node.operands:
            value = self.visit(operand)
            if value is UNKNOWN:
                unknown = True
            elif value is decisive:
                return decisive
        return UNKNOWN if unknown else not decisive

    def visit_implies(self, node: Implies) -> object:
        result: object = self.visit(node.operands[-1])
        for operand in reversed(node.operands[:-1]):
            premise = self.visit(operand)
            if premise is False or result is True:
                result = True
            elif premise is True:
                pass
            else:
                result = UNKNOWN
        return result

    def visit_compare(self, node: Compare) -> object:
        values = [self.visit(operand) for operand in node.operands]
        unknown = False
        for index, op in enumerate(node.ops):
            left, right = values[index], values[index + 1]
            if left is UNKNOWN or right is UNKNOWN:
                unknown = True
                continue
            if not _CMP[op](left, right):
                return False
        return UNKNOWN if unknown else True

    def visit_sum(self, node: Sum) -> object:
        total: Fraction = Fraction(0)
        for op, term in node.terms:
            value = self.visit(term)
            if value is UNKNOWN:
                return UNKNOWN
            total = total + value if op == "+" else total - value  # type: ignore[operator]
        return total

    def visit_product(self, node: Product) -> object:
        product: Fraction = Fraction(1)
        for op, factor in node.factors:
            value = self.visit(factor)
            if value is UNKNOWN:
                return UNKNOWN
            if op == "/":
                if value == 0:
                    return UNKNOWN
                product = product / value  # type: ignore[operator]
            else:
                product = product * value  # type: ignore[operator]
        return product
