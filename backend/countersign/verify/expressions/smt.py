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
    Special,
    Sum,
    Text,
    Truth,
)
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


class Translator:
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
        if isinstance(expr, Num):
            if expr.integral:
                return smt_int(int(expr.value)), "integer"
            return smt_real(expr.value), "real"
        if isinstance(expr, Text):
            return smt_int(self.string_code(expr.value)), "string"
        if isinstance(expr, Truth):
            return ("true" if expr.value else "false"), "boolean"
        if isinstance(expr, Name):
            return self.quantity(expr.name)
        if isinstance(expr, Special):
            return self.special(expr.name), "string"
        if isinstance(expr, Context):
            return self.context(expr.tag), "boolean"
        if isinstance(expr, Not):
            return f"(not {self.condition(expr.operand)})", "boolean"
        if isinstance(expr, Neg):
            inner, inner_kind = self.term(expr.operand)
            return f"(- {inner})", inner_kind
        if isinstance(expr, Logic):
            parts = " ".join(self.condition(o) for o in expr.operands)
            return f"({expr.op} {parts})", "boolean"
        if isinstance(expr, Implies):
            text = self.condition(expr.operands[-1])
            for operand in reversed(expr.operands[:-1]):
                text = f"(=> {self.condition(operand)} {text})"
            return text, "boolean"
        if isinstance(expr, Compare):
            return self._compare(expr), "boolean"
        if isinstance(expr, Sum):
            items = [(op, *self.term(t)) for op, t in expr.terms]
            kind: Kind = "integer" if all(k == "integer" for _, _, k in items) else "real"
            text = self._coerce(items[0][1], items[0][2], kind)
            for op, term, term_kind in items[1:]:
                text = f"({op} {text} {self._coerce(term, term_kind, kind)})"
            return text, kind
        factors = [(op, *self.term(f)) for op, f in expr.factors]
        divides = any(op == "/" for op, _, _ in factors)
        kind = "integer" if all(k == "integer" for _, _, k in factors) and not divides \
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
