"""Checked conditions in words, for the text a supervisor signs.

A constraint's text says what the author meant; its condition is what the checks and the
vehicle test. The plain orders show both ("checked as: depth at least 20 m (`depth_m >= 20`)"),
so a limit can never be signed without being read.
"""

from __future__ import annotations

from collections.abc import Mapping

from .expressions import (
    Compare,
    Expr,
    ExprError,
    Implies,
    Logic,
    Not,
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
    if isinstance(expr, Compare):
        unit = _unit_of(expr, quantities)
        words = describe(expr.operands[0], quantities, unit)
        for op, operand in zip(expr.ops, expr.operands[1:], strict=True):
            words += f" {_OPS.get(op, op)} {describe(operand, quantities, unit)}"
        return words
    if isinstance(expr, Logic):
        parts = [_grouped(o, quantities) for o in expr.operands]
        return f" {expr.op} ".join(parts)
    if isinstance(expr, Implies):
        first, *rest = expr.operands
        then = " implies ".join(_grouped(o, quantities) for o in rest)
        return f"if {_grouped(first, quantities)} then {then}"
    if isinstance(expr, Not):
        return f"not {_grouped(expr.operand, quantities)}"
    return describe(expr, quantities)


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
