"""Translation to SMT-LIB (and to z3 terms through z3's own SMT-LIB reader)."""

from __future__ import annotations

from collections.abc import Mapping
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
from ...orders.model import Quantity
from .types import Kind


def smt_real(value: Fraction) -> str:
    magnitude = abs(value)
    if magnitude.denominator == 1:
        text = f"{magnitude.numerator}.0"
    else:
        text = f"(/ {magnitude.numerator}.0 {magnitude.denominator}.0)"
    return f"(- {text})" if value < 0 else text


def smt_int(value: int) -> str:
    return f"(- {-value})" if value < 0 else str(value)


class Translator(ExprVisitor[tuple[str, Kind]]):
    """Translates type-checked expressions to SMT-LIB terms.

    Quantities become constants `|q:name|` (Real, Int or Bool by their declared type),
    `behavior` and `area` Int constants whose values are codes of interned strings, and
    `context('tag')` a Bool constant per tag. A suffix (e.g. "@G1") gives each goal its own
    copy of the state. `symbols` collects every constant used, with its sort, so that a caller
    can declare them before asserting the terms.
    """

    def __init__(self, quantities: Mapping[str, Quantity], strings: dict[str, int] | None = None,
                 suffix: str = "") -> None:
        self.quantities = quantities
        self.strings = strings if strings is not None else {}
        self.suffix = suffix
        self.symbols: dict[str, str] = {}

    def with_suffix(self, suffix: str) -> Translator:
        other = Translator(self.quantities, self.strings, suffix)
        other.symbols = self.symbols
        return other

    # Symbols -----------------------------------------------------------------------------

    def string_code(self, value: str | None) -> int:
        if value is None:
            return -1
        code = self.strings.get(value)
        if code is None:
            # The string's own bytes as a number (a leading 1 keeps it injective): the same
            # string has the same code in every session, so a formula's text, and the model z3
            # finds for it, do not depend on which strings were translated before.
            code = self.strings[value] = int.from_bytes(b"\x01" + value.encode(), "big")
        return code

    def quantity(self, name: str) -> tuple[str, Kind]:
        spec = self.quantities.get(name)
        kind: Kind = "real"
        sort = "Real"
        if spec is not None and spec.type == "integer":
            kind, sort = "integer", "Int"
        elif spec is not None and spec.type == "boolean":
            kind, sort = "boolean", "Bool"
        symbol = f"|q:{name}{self.suffix}|"
        self.symbols[symbol] = sort
        return symbol, kind

    def special(self, name: str) -> str:
        symbol = f"|{name}{self.suffix}|"
        self.symbols[symbol] = "Int"
        return symbol

    def context(self, tag: str) -> str:
        symbol = f"|ctx:{self.string_code(tag)}{self.suffix}|"
        self.symbols[symbol] = "Bool"
        return symbol

    def declarations(self, skip: set[str] | None = None) -> str:
        return "".join(
            f"(declare-const {symbol} {sort})"
            for symbol, sort in self.symbols.items()
            if skip is None or symbol not in skip
        )

    # Terms -------------------------------------------------------------------------------

    def condition(self, expr: Expr) -> str:
        text, _ = self.term(expr)
        return text

    def term(self, expr: Expr) -> tuple[str, Kind]:
        return self.visit(expr)

    def visit_num(self, node: Num) -> tuple[str, Kind]:
        if node.integral:
            return smt_int(int(node.value)), "integer"
        return smt_real(node.value), "real"

    def visit_text(self, node: Text) -> tuple[str, Kind]:
        return smt_int(self.string_code(node.value)), "string"

    def visit_truth(self, node: Truth) -> tuple[str, Kind]:
        return ("true" if node.value else "false"), "boolean"

    def visit_name(self, node: Name) -> tuple[str, Kind]:
        return self.quantity(node.name)

    def visit_special(self, node: Special) -> tuple[str, Kind]:
        return self.special(node.name), "string"

    def visit_context(self, node: Context) -> tuple[str, Kind]:
        return self.context(node.tag), "boolean"

    def visit_not(self, node: Not) -> tuple[str, Kind]:
        return f"(not {self.condition(node.operand)})", "boolean"

    def visit_neg(self, node: Neg) -> tuple[str, Kind]:
        inner, inner_kind = self.term(node.operand)
        return f"(- {inner})", inner_kind

    def visit_logic(self, node: Logic) -> tuple[str, Kind]:
        parts = " ".join(self.condition(o) for o in node.operands)
        return f"({node.op} {parts})", "boolean"

    def visit_implies(self, node: Implies) -> tuple[str, Kind]:
        text = self.condition(node.operands[-1])
        for operand in reversed(node.operands[:-1]):
            text = f"(=> {self.condition(operand)} {text})"
        return text, "boolean"

    def visit_compare(self, node: Compare) -> tuple[str, Kind]:
        return self._compare(node), "boolean"

    def visit_sum(self, node: Sum) -> tuple[str, Kind]:
        items = [(op, *self.term(t)) for op, t in node.terms]
        kind: Kind = "integer" if all(k == "integer" for _, _, k in items) else "real"
        text = self._coerce(items[0][1], items[0][2], kind)
        for op, term, term_kind in items[1:]:
            text = f"({op} {text} {self._coerce(term, term_kind, kind)})"
        return text, kind

    def visit_product(self, node: Product) -> tuple[str, Kind]:
        factors = [(op, *self.term(f)) for op, f in node.factors]
        divides = any(op == "/" for op, _, _ in factors)
        kind: Kind = "integer" if all(k == "integer" for _, _, k in factors) and not divides \
            else "real"
        text = self._coerce(factors[0][1], factors[0][2], kind)
        for op, factor, factor_kind in factors[1:]:
            text = f"({op} {text} {self._coerce(factor, factor_kind, kind)})"
        return text, kind

    @staticmethod
    def _coerce(text: str, kind: Kind, target: Kind) -> str:
        if target == "real" and kind == "integer":
            return f"(to_real {text})"
        return text

    def _compare(self, expr: Compare) -> str:
        terms = [self.term(operand) for operand in expr.operands]
        parts: list[str] = []
        for index, op in enumerate(expr.ops):
            (left, left_kind), (right, right_kind) = terms[index], terms[index + 1]
            if {left_kind, right_kind} == {"integer", "real"}:
                left = self._coerce(left, left_kind, "real")
                right = self._coerce(right, right_kind, "real")
            if op == "==":
                parts.append(f"(= {left} {right})")
            elif op == "!=":
                parts.append(f"(not (= {left} {right}))")
            else:
                parts.append(f"({op} {left} {right})")
        return parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})"


def to_smtlib(expr: Expr, quantities: Mapping[str, Quantity]) -> tuple[str, str]:
    """(declarations, term) of a type-checked condition, as SMT-LIB text."""
    translator = Translator(quantities)
    term = translator.condition(expr)
    return translator.declarations(), term


def to_z3(expr: Expr, quantities: Mapping[str, Quantity], ctx: object | None = None) -> object:
    """A z3 BoolRef for a type-checked condition (read back through z3's SMT-LIB parser, so the
    solver sees exactly the text the logic checks assert)."""
    import z3

    declarations, term = to_smtlib(expr, quantities)
    vector = z3.parse_smt2_string(f"{declarations}(assert {term})", ctx=ctx)
    return vector[0]
