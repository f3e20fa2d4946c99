"""Constraint conditions as MOOS-IvP helm logic conditions, where the helm can express them.

The helm compares a MOOS variable with a literal and combines comparisons with `and`/`or`;
arithmetic, `behavior`/`area` and `context(...)` have no helm counterpart. The violation of a
constraint is its negation, pushed down to the comparisons (De Morgan) so no `!` is needed."""

from __future__ import annotations

from fractions import Fraction

from ..verify.expressions import (
    Compare,
    Expr,
    ExprError,
    Implies,
    Logic,
    Name,
    Not,
    Num,
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
    if isinstance(expr, Name):
        return f"({variable(expr.name)} = {'true' if holds else 'false'})"
    if isinstance(expr, Not):
        return helm_condition(expr.operand, not holds)
    if isinstance(expr, Compare):
        parts = [_comparison(expr.operands[i], op, expr.operands[i + 1], holds)
                 for i, op in enumerate(expr.ops)]
        return _join("and" if holds else "or", parts)
    if isinstance(expr, Logic):
        op = expr.op if holds else ("or" if expr.op == "and" else "and")
        return _join(op, [helm_condition(e, holds) for e in expr.operands])
    if isinstance(expr, Implies):
        # a implies (b implies c): not a or (not b or c)
        *premises, conclusion = expr.operands
        parts = [helm_condition(p, not holds) for p in premises]
        parts.append(helm_condition(conclusion, holds))
        return _join("or" if holds else "and", parts)
    return None


def violation(source: str | None) -> str | None:
    """Helm condition for "this constraint is broken", or None when it cannot be said."""
    if not source:
        return None
    try:
        return helm_condition(parse(source), holds=False)
    except ExprError:
        return None
