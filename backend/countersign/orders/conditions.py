"""Checked conditions in words, for the text a supervisor signs.

A constraint's text says what the author meant; its condition is what the checks and the
vehicle test. The plain orders show both ("checked as: depth at least 20 m (`depth_m >= 20`)"),
so a limit can never be signed without being read.
"""

from __future__ import annotations

from collections.abc import Mapping

from .expressions import (
    Compare,
    Context,
    Expr,
    ExprError,
    ExprVisitor,
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
    describe,
    parse,
    quantity_table,
)
from .model import Orders, Quantity

# Comparison operators as a reader says them; the symbols follow in the code span.
_OPS = {
    ">=": "at least", "<=": "at most", ">": "above", "<": "below", "==": "is", "!=": "is not",
}


def _unit_of(expr: Compare, quantities: Mapping[str, Quantity]) -> str:
    for operand in expr.operands:
        name = getattr(operand, "name", None)
        spec = quantities.get(name) if isinstance(name, str) else None
        if spec is not None and spec.unit:
            return spec.unit
    return ""


def expr_words(expr: Expr, quantities: Mapping[str, Quantity]) -> str:
    """The condition in words: comparisons as 'at least', 'at most', connectives spelled out."""
    return _ConditionWords(quantities).visit(expr)


class _ConditionWords(ExprVisitor[str]):
    """Comparisons and connectives are said here; every other kind as `describe` says it."""

    __slots__ = ("quantities",)

    def __init__(self, quantities: Mapping[str, Quantity]) -> None:
        self.quantities = quantities

    def visit_num(self, node: Num) -> str:
        return describe(node, self.quantities)

    def visit_text(self, node: Text) -> str:
        return describe(node, self.quantities)

    def visit_truth(self, node: Truth) -> str:
        return describe(node, self.quantities)

    def visit_name(self, node: Name) -> str:
        return describe(node, self.quantities)

    def visit_special(self, node: Special) -> str:
        return describe(node, self.quantities)

    def visit_context(self, node: Context) -> str:
        return describe(node, self.quantities)

    def visit_neg(self, node: Neg) -> str:
        return describe(node, self.quantities)

    def visit_sum(self, node: Sum) -> str:
        return describe(node, self.quantities)

    def visit_product(self, node: Product) -> str:
        return describe(node, self.quantities)

    def visit_compare(self, node: Compare) -> str:
        quantities = self.quantities
        unit = _unit_of(node, quantities)
        words = describe(node.operands[0], quantities, unit)
        for op, operand in zip(node.ops, node.operands[1:], strict=True):
            words += f" {_OPS.get(op, op)} {describe(operand, quantities, unit)}"
        return words

    def visit_logic(self, node: Logic) -> str:
        parts = [_grouped(o, self.quantities) for o in node.operands]
        return f" {node.op} ".join(parts)

    def visit_implies(self, node: Implies) -> str:
        first, *rest = node.operands
        then = " implies ".join(_grouped(o, self.quantities) for o in rest)
        return f"if {_grouped(first, self.quantities)} then {then}"

    def visit_not(self, node: Not) -> str:
        return f"not {_grouped(node.operand, self.quantities)}"


def _grouped(expr: Expr, quantities: Mapping[str, Quantity]) -> str:
    text = expr_words(expr, quantities)
    return f"({text})" if isinstance(expr, Logic | Implies) else text


def condition_words(source: str | None, quantities: Mapping[str, Quantity]) -> str:
    """'checked as: depth at least 20 m (`depth_m >= 20`)', or why nothing is checked."""
    if source is None or not source.strip():
        return "Not checked: the orders give no condition."
    code = " ".join(source.split())
    try:
        words = expr_words(parse(source), quantities)
    except ExprError:
        return f"Not checked: the condition (`{code}`) cannot be read."
    return f"Checked as: {words} (`{code}`)."


def quantities_of(orders: Orders) -> dict[str, Quantity]:
    return quantity_table(orders)
