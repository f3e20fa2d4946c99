"""The expression tree: small immutable nodes; `col` is the 1-based column where a node starts."""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Literal


@dataclass(frozen=True, slots=True)
class Num:
    value: Fraction
    integral: bool
    col: int


@dataclass(frozen=True, slots=True)
class Text:
    value: str
    col: int


@dataclass(frozen=True, slots=True)
class Truth:
    value: bool
    col: int


@dataclass(frozen=True, slots=True)
class Name:
    """A quantity."""

    name: str
    col: int


@dataclass(frozen=True, slots=True)
class Special:
    """`behavior` or `area`: the goal's behaviour string or area id."""

    name: Literal["behavior", "area"]
    col: int


@dataclass(frozen=True, slots=True)
class Context:
    """`context('tag')`: true when the goal's area carries the tag."""

    tag: str
    col: int


@dataclass(frozen=True, slots=True)
class Neg:
    operand: Expr
    col: int


@dataclass(frozen=True, slots=True)
class Not:
    operand: Expr
    col: int


@dataclass(frozen=True, slots=True)
class Sum:
    """terms[0] is ('+', first); the rest are ('+' | '-', term), folded left."""

    terms: tuple[tuple[str, Expr], ...]
    col: int


@dataclass(frozen=True, slots=True)
class Product:
    """factors[0] is ('*', first); the rest are ('*' | '/', factor), folded left."""

    factors: tuple[tuple[str, Expr], ...]
    col: int


@dataclass(frozen=True, slots=True)
class Compare:
    """operands[0] ops[0] operands[1] ops[1] operands[2] ...: a chain means `and`."""

    operands: tuple[Expr, ...]
    ops: tuple[str, ...]
    col: int


@dataclass(frozen=True, slots=True)
class Logic:
    op: Literal["and", "or"]
    operands: tuple[Expr, ...]
    col: int


@dataclass(frozen=True, slots=True)
class Implies:
    """operands[0] implies (operands[1] implies (...))."""

    operands: tuple[Expr, ...]
    col: int


Expr = Num | Text | Truth | Name | Special | Context | Neg | Not | Sum | Product | Compare \
    | Logic | Implies
