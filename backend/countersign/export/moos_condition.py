"""Constraint conditions as MOOS-IvP helm logic conditions, where the helm can express them.

The helm compares a MOOS variable with a literal and combines comparisons with `and`/`or`;
arithmetic, `behavior`/`area` and `context(...)` have no helm counterpart. The violation of a
constraint is its negation, pushed down to the comparisons (De Morgan) so no `!` is needed."""

from __future__ import annotations

from fractions import Fraction

from ..verify.expressions import (
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
    parse,
)

_NEGATED = {"<": ">=", "<=": ">", ">": "<=", ">=": "<", "==": "!=", "!=": "=="}
_MIRRORED = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}


def variable(name: str) -> str:
    return name.upper()


def _literal(expr: Expr) -> str | None:
    if isinstance(expr, Num):
        value: Fraction = expr.value
        return str(int(value)) if value.denominator == 1 else repr(float(value))
    if isinstance(expr, Truth):
        return "true" if expr.value else "false"
    if isinstance(expr, Text) and expr.value.replace("_", "").isalnum():
        return expr.value
    return None


def _comparison(left: Expr, op: str, right: Expr, holds: bool) -> str | None:
    if isinstance(right, Name) and not isinstance(left, Name):
        left, right, op = right, left, _MIRRORED[op]
    literal = _literal(right)
    if not isinstance(left, Name) or literal is None:
        return None
    return f"({variable(left.name)} {op if holds else _NEGATED[op]} {literal})"


def _join(op: str, parts: list[str | None]) -> str | None:
    if any(p is None for p in parts):
        return None
    return parts[0] if len(parts) == 1 else "(" + f" {op} ".join(p for p in parts if p) + ")"


def helm_condition(expr: Expr, holds: bool = True) -> str | None:
    """The condition true exactly when `expr` holds (or, with holds=False, is broken)."""
    return _Helm(holds).visit(expr)


class _Helm(ExprVisitor[str | None]):
    """A helm condition, or None for the kinds the helm cannot express on their own."""

    __slots__ = ("holds",)

    def __init__(self, holds: bool) -> None:
        self.holds = holds

    def visit_num(self, node: Num) -> str | None:
        return None

    def visit_text(self, node: Text) -> str | None:
        return None

    def visit_truth(self, node: Truth) -> str | None:
        return None

    def visit_name(self, node: Name) -> str | None:
        return f"({variable(node.name)} = {'true' if self.holds else 'false'})"

    def visit_special(self, node: Special) -> str | None:
        return None

    def visit_context(self, node: Context) -> str | None:
        return None

    def visit_neg(self, node: Neg) -> str | None:
        return None

    def visit_not(self, node: Not) -> str | None:
        return helm_condition(node.operand, not self.holds)

    def visit_sum(self, node: Sum) -> str | None:
        return None

    def visit_product(self, node: Product) -> str | None:
        return None

    def visit_compare(self, node: Compare) -> str | None:
        holds = self.holds
        parts = [_comparison(node.operands[i], op, node.operands[i + 1], holds)
                 for i, op in enumerate(node.ops)]
        return _join("and" if holds else "or", parts)

    def visit_logic(self, node: Logic) -> str | None:
        holds = self.holds
        op = node.op if holds else ("or" if node.op == "and" else "and")
        return _join(op, [helm_condition(e, holds) for e in node.operands])

    def visit_implies(self, node: Implies) -> str | None:
        # a implies (b implies c): not a or (not b or c)
        holds = self.holds
        *premises, conclusion = node.operands
        parts = [helm_condition(p, not holds) for p in premises]
        parts.append(helm_condition(conclusion, holds))
        return _join("or" if holds else "and", parts)


def violation(source: str | None) -> str | None:
    """Helm condition for "this constraint is broken", or None when it cannot be said."""
    if not source:
        return None
    try:
        return helm_condition(parse(source), holds=False)
    except ExprError:
        return None
