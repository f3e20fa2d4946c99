"""Plain words for explanations: names become titles, numbers compared with a quantity get
their unit. The signed plain text of the orders (orders/plain.py, conditions.py) uses them, so
they live beside the syntax rather than in verify."""

from __future__ import annotations

import math
from collections.abc import Mapping
from fractions import Fraction

from ..model import Quantity
from .tree import (
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
from .visit import ExprVisitor

_WORD_OPS = {"==": "is", "!=": "is not"}


def quantity_words(name: str, quantities: Mapping[str, Quantity]) -> str:
    spec = quantities.get(name)
    title = spec.title if spec is not None and spec.title else name
    if len(title) > 1 and title[0].isupper() and not title[1].isupper():
        title = title[0].lower() + title[1:]
    return title


def number_words(value: Fraction | float) -> str:
    number = float(value)
    if not math.isfinite(number):
        return str(number)
    if number == int(number) and abs(number) < 1e15:
        return f"{int(number):,}"
    return f"{number:,.6g}"


def with_unit(value: str, unit: str) -> str:
    if not unit:
        return value
    return f"{value} {unit}" if unit not in {"%", "deg"} else (
        f"{value} %" if unit == "%" else f"{value}°"
    )


def tag_words(tag: str) -> str:
    return tag.replace("_", " ")


def with_article(words: str) -> str:
    return f"an {words}" if words[:1].lower() in "aeiou" else f"a {words}"


# Tags that name a kind of place read "a shipping lane"; others ("coastal") describe one.
_PLACE_NOUNS = frozenset({
    "area", "lane", "zone", "channel", "approach", "reserve", "sanctuary", "park", "harbor",
    "harbour", "port", "corridor", "range", "box", "anchorage", "field", "ground", "grounds",
    "site", "route", "passage", "strait", "bay", "basin", "reef", "wreck", "waters", "region",
})


def _is_place(tag: str) -> bool:
    words = tag_words(tag).split()
    return bool(words) and words[-1].lower() in _PLACE_NOUNS


def tag_state(tag: str, holds: bool = True) -> str:
    """'is a shipping lane' / 'is coastal' (or their negations)."""
    words = tag_words(tag)
    if _is_place(tag):
        words = with_article(words)
    return f"is {words}" if holds else f"is not {words}"


def in_tag(tag: str) -> str:
    """'in a shipping lane' / 'in a coastal area'."""
    words = tag_words(tag)
    return f"in {with_article(words)}" if _is_place(tag) else f"in {with_article(words)} area"


def describe(expr: Expr, quantities: Mapping[str, Quantity], unit: str = "") -> str:
    """The expression in words a supervisor reads, e.g. 'depth >= 20 m'."""
    return _Words(quantities, unit).visit(expr)


class _Words(ExprVisitor[str]):
    """`unit` is the unit of the comparison or sum a number stands in, given to its numbers."""

    __slots__ = ("quantities", "unit")

    def __init__(self, quantities: Mapping[str, Quantity], unit: str) -> None:
        self.quantities = quantities
        self.unit = unit

    def visit_num(self, node: Num) -> str:
        return with_unit(number_words(node.value), self.unit)

    def visit_text(self, node: Text) -> str:
        return repr(node.value)

    def visit_truth(self, node: Truth) -> str:
        return "true" if node.value else "false"

    def visit_name(self, node: Name) -> str:
        return quantity_words(node.name, self.quantities)

    def visit_special(self, node: Special) -> str:
        return node.name

    def visit_context(self, node: Context) -> str:
        return in_tag(node.tag)

    def visit_not(self, node: Not) -> str:
        return f"not {_grouped(node.operand, self.quantities, 'not')}"

    def visit_neg(self, node: Neg) -> str:
        return f"-{_grouped(node.operand, self.quantities, 'arith', self.unit)}"

    def visit_logic(self, node: Logic) -> str:
        return f" {node.op} ".join(_grouped(o, self.quantities, node.op) for o in node.operands)

    def visit_implies(self, node: Implies) -> str:
        return " implies ".join(_grouped(o, self.quantities, "implies") for o in node.operands)

    def visit_compare(self, node: Compare) -> str:
        quantities = self.quantities
        unit = _unit_of(node.operands, quantities)
        words = describe(node.operands[0], quantities, unit)
        for op, operand in zip(node.ops, node.operands[1:], strict=True):
            words += f" {_WORD_OPS.get(op, op)} {_grouped(operand, quantities, 'compare', unit)}"
        return words

    def visit_sum(self, node: Sum) -> str:
        quantities = self.quantities
        unit = self.unit or _unit_of([t for _, t in node.terms], quantities)
        words = _grouped(node.terms[0][1], quantities, "sum", unit)
        for op, term in node.terms[1:]:
            words += f" {op} {_grouped(term, quantities, 'sum', unit)}"
        return words

    def visit_product(self, node: Product) -> str:
        quantities = self.quantities
        words = _grouped(node.factors[0][1], quantities, "product")
        for op, factor in node.factors[1:]:
            words += f" {op} {_grouped(factor, quantities, 'product')}"
        return words


# Which children need parentheses inside which parents.
_GROUP = {
    "not": (Logic, Implies, Compare),
    "and": (Logic, Implies),
    "or": (Logic, Implies),
    "implies": (Implies,),
    "compare": (Compare, Logic, Implies),
    "sum": (Sum, Compare, Logic, Implies),
    "product": (Sum, Product, Compare, Logic, Implies),
    "arith": (Sum, Product, Compare, Logic, Implies),
}


def _grouped(expr: Expr, quantities: Mapping[str, Quantity], parent: str, unit: str = "") -> str:
    text = describe(expr, quantities, unit)
    if isinstance(expr, _GROUP[parent]) and not (
        isinstance(expr, Logic) and expr.op == parent
    ):
        return f"({text})"
    return text


def _unit_of(operands: tuple[Expr, ...] | list[Expr], quantities: Mapping[str, Quantity]) -> str:
    for operand in operands:
        if isinstance(operand, Name):
            spec = quantities.get(operand.name)
            if spec is not None and spec.unit:
                return spec.unit
    return ""
