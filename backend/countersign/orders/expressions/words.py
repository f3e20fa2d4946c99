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
    if isinstance(expr, Num):
        return with_unit(number_words(expr.value), unit)
    if isinstance(expr, Text):
        return repr(expr.value)
    if isinstance(expr, Truth):
        return "true" if expr.value else "false"
    if isinstance(expr, Name):
        return quantity_words(expr.name, quantities)
    if isinstance(expr, Special):
        return expr.name
    if isinstance(expr, Context):
        return in_tag(expr.tag)
    if isinstance(expr, Not):
        return f"not {_grouped(expr.operand, quantities, 'not')}"
    if isinstance(expr, Neg):
        return f"-{_grouped(expr.operand, quantities, 'arith', unit)}"
    if isinstance(expr, Logic):
        return f" {expr.op} ".join(_grouped(o, quantities, expr.op) for o in expr.operands)
    if isinstance(expr, Implies):
        return " implies ".join(_grouped(o, quantities, "implies") for o in expr.operands)
    if isinstance(expr, Compare):
        unit = _unit_of(expr.operands, quantities)
        words = describe(expr.operands[0], quantities, unit)
        for op, operand in zip(expr.ops, expr.operands[1:], strict=True):
            words += f" {_WORD_OPS.get(op, op)} {_grouped(operand, quantities, 'compare', unit)}"
        return words
    if isinstance(expr, Sum):
        unit = unit or _unit_of([t for _, t in expr.terms], quantities)
        words = _grouped(expr.terms[0][1], quantities, "sum", unit)
        for op, term in expr.terms[1:]:
            words += f" {op} {_grouped(term, quantities, 'sum', unit)}"
        return words
    words = _grouped(expr.factors[0][1], quantities, "product")
    for op, factor in expr.factors[1:]:
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
