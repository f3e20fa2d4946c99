"""Types and units: the type checker that accepts or refuses a condition against the
quantities the orders declare."""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from ...orders.expressions.errors import ExprError
from ...orders.expressions.lexer import RESERVED
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
from ...orders.model import Quantity

Kind = Literal["boolean", "integer", "real", "string"]

@dataclass(frozen=True, slots=True)
class Typed:
    kind: Kind
    unit: str | None  # None: no unit to compare (a literal, a product, an undeclared unit)


_NUMERIC = ("integer", "real")
_KIND_WORD = {"boolean": "a condition", "integer": "a number", "real": "a number",
              "string": "text"}


def _numeric(kind: Kind) -> bool:
    return kind in _NUMERIC


def _join_units(units: list[tuple[str | None, int]], verb: str) -> str | None:
    known = [(u, col) for u, col in units if u]
    if not known:
        return None
    first, _ = known[0]
    for unit, col in known[1:]:
        if unit != first:
            raise ExprError(f"{verb} {first} with {unit}: the units differ", col)
    return first


class TypeChecker(ExprVisitor[Typed]):
    """Checks an expression against a quantity table. Unknown names and type or unit errors
    raise ExprError with the column of the offending part."""

    def __init__(self, quantities: Mapping[str, Quantity]) -> None:
        self.quantities = quantities

    def condition(self, expr: Expr) -> None:
        typed = self.check(expr)
        if typed.kind != "boolean":
            raise ExprError(
                f"this is {_KIND_WORD[typed.kind]}, not a condition (compare it with "
                "something, e.g. depth_m >= 20)",
                expr.col,
            )

    def check(self, expr: Expr) -> Typed:
        return self.visit(expr)

    def visit_num(self, node: Num) -> Typed:
        return Typed("integer" if node.integral else "real", None)

    def visit_text(self, node: Text) -> Typed:
        return Typed("string", None)

    def visit_truth(self, node: Truth) -> Typed:
        return Typed("boolean", None)

    def visit_context(self, node: Context) -> Typed:
        return Typed("boolean", None)

    def visit_special(self, node: Special) -> Typed:
        return Typed("string", None)

    def visit_name(self, node: Name) -> Typed:
        return self._name(node)

    def visit_neg(self, node: Neg) -> Typed:
        return self._require_number(node.operand, "'-'")

    def visit_not(self, node: Not) -> Typed:
        self._require_condition(node.operand, "not")
        return Typed("boolean", None)

    def visit_sum(self, node: Sum) -> Typed:
        return self._sum(node)

    def visit_product(self, node: Product) -> Typed:
        return self._product(node)

    def visit_compare(self, node: Compare) -> Typed:
        return self._compare(node)

    def visit_logic(self, node: Logic) -> Typed:
        for operand in node.operands:
            self._require_condition(operand, node.op)
        return Typed("boolean", None)

    def visit_implies(self, node: Implies) -> Typed:
        for operand in node.operands:
            self._require_condition(operand, "implies")
        return Typed("boolean", None)

    def _name(self, expr: Name) -> Typed:
        quantity = self.quantities.get(expr.name)
        if quantity is None:
            hint = ""
            if expr.name.lower() in RESERVED:
                hint = f" (write {expr.name.lower()!r} in lower case)"
            else:
                close = difflib.get_close_matches(expr.name, list(self.quantities), n=1)
                if close:
                    hint = f" (did you mean {close[0]!r}?)"
            raise ExprError(f"unknown quantity {expr.name!r}{hint}", expr.col)
        kind: Kind = "real"
        if quantity.type == "integer":
            kind = "integer"
        elif quantity.type == "boolean":
            kind = "boolean"
        return Typed(kind, quantity.unit or None)

    def _require_number(self, expr: Expr, where: str) -> Typed:
        typed = self.check(expr)
        if not _numeric(typed.kind):
            raise ExprError(f"{where} needs a number, but this is {_KIND_WORD[typed.kind]}",
                            expr.col)
        return typed

    def _require_condition(self, expr: Expr, where: str) -> None:
        typed = self.check(expr)
        if typed.kind != "boolean":
            raise ExprError(
                f"{where!r} needs a condition, but this is {_KIND_WORD[typed.kind]}", expr.col
            )

    def _sum(self, expr: Sum) -> Typed:
        kinds: list[Kind] = []
        units: list[tuple[str | None, int]] = []
        for op, term in expr.terms:
            typed = self._require_number(term, f"{op!r}")
            kinds.append(typed.kind)
            units.append((typed.unit, term.col))
        unit = _join_units(units, "adds")
        return Typed("integer" if all(k == "integer" for k in kinds) else "real", unit)

    def _product(self, expr: Product) -> Typed:
        kinds: list[Kind] = []
        units: list[str | None] = []
        for op, factor in expr.factors:
            typed = self._require_number(factor, f"{op!r}")
            kinds.append(typed.kind)
            units.append(typed.unit)
            if op == "/" and isinstance(factor, Num) and factor.value == 0:
                raise ExprError("division by zero", factor.col)
        divides = any(op == "/" for op, _ in expr.factors)
        kind: Kind = "integer" if all(k == "integer" for k in kinds) and not divides else "real"
        # Scaling by literals keeps the unit (2 * depth_m and depth_m / 2 are in metres);
        # anything else is a derived unit that is not compared.
        scaled = [(op, unit) for (op, factor), unit in zip(expr.factors, units, strict=True)
                  if not isinstance(factor, Num)]
        unit = scaled[0][1] if len(scaled) == 1 and scaled[0][0] == "*" else None
        return Typed(kind, unit)

    def _compare(self, expr: Compare) -> Typed:
        typed = [self.check(operand) for operand in expr.operands]
        for index, op in enumerate(expr.ops):
            left, right = typed[index], typed[index + 1]
            node = expr.operands[index + 1]
            if op in {"==", "!="}:
                if _numeric(left.kind) and _numeric(right.kind):
                    _join_units([(left.unit, 0), (right.unit, node.col)], "compares")
                    continue
                if left.kind != right.kind:
                    raise ExprError(
                        f"{op!r} compares {_KIND_WORD[left.kind]} with "
                        f"{_KIND_WORD[right.kind]}",
                        node.col,
                    )
                continue
            for side, operand in ((left, expr.operands[index]), (right, node)):
                if not _numeric(side.kind):
                    hint = " (text can only be compared with == or !=)" \
                        if side.kind == "string" else ""
                    raise ExprError(
                        f"{op!r} needs numbers, but this is {_KIND_WORD[side.kind]}{hint}",
                        operand.col,
                    )
            _join_units([(left.unit, 0), (right.unit, node.col)], "compares")
        return Typed("boolean", None)


def check_condition(expr: Expr, quantities: Mapping[str, Quantity]) -> None:
    TypeChecker(quantities).condition(expr)
