"""Items: the statements the solver sees, each behind its own indicator literal."""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from functools import partial
from typing import Any

from ...orders.model import Quantity
from ..expressions import (
    Expr,
    Translator,
    number_words,
    smt_int,
    smt_real,
    with_unit,
)
from .constants import ItemKind


@dataclass(frozen=True)
class Part:
    """What a core reports about one item: enough to explain it, nothing to solve it."""

    key: str
    kind: str
    subject: str
    phrase: str

    def to_json(self) -> dict[str, str]:
        return {"key": self.key, "kind": self.kind, "subject": self.subject, "text": self.phrase}


class Item:
    """One statement for the solver, asserted behind its own indicator literal. Its phrase is
    built only when a core reports it."""

    __slots__ = ("_phrase", "digest", "extra", "formula", "key", "kind", "meaning",
                 "quantities", "said", "shared", "source", "subject")

    def __init__(
        self,
        key: str,
        kind: ItemKind,
        subject: str,
        phrase: str | Callable[[], str],
        source: str,
        formula: Callable[[Translator], str],
        shared: bool = True,
        quantities: tuple[str, ...] = (),
        meaning: tuple[Any, ...] | None = None,
    ) -> None:
        self.key = key
        self.kind = kind
        self.subject = subject
        self._phrase = phrase
        # Everything that determines the formula and the phrase: what a cache key digests.
        self.source = source
        self.formula = formula
        # Asserted once per session (same formula for every goal) rather than per goal scope.
        self.shared = shared
        self.quantities = quantities
        # What bounds.py decides from, without z3: ("box", quantity, low, high), ("fact", what,
        # value) or ("expr", memo key, (expression, negated)); None: z3 only.
        self.meaning = meaning
        # What the item states, whoever states it (bounds.py keys its answers by it: goals with
        # the same envelope, facts and constraints ask the same question); None: z3 only.
        self.said = None if meaning is None else meaning[1] if meaning[0] == "expr" else meaning
        # A norm or a breach: what a goal's checks add, one at a time, to its own statements.
        self.extra = kind in _EXTRA_KINDS
        # Every item ends up in some unit's cache key: an attribute, not a property, so a key
        # of hundreds of items is read at C speed.
        self.digest = hashlib.sha256(source.encode()).digest()

    @property
    def phrase(self) -> str:
        if not isinstance(self._phrase, str):
            self._phrase = self._phrase()
        return self._phrase

    def word(self) -> None:
        """Word the phrase now (and let go of what wording it needed)."""
        if not isinstance(self._phrase, str):
            self._phrase = self._phrase()

    @property
    def part(self) -> Part:
        return Part(self.key, self.kind, self.subject, self.phrase)

    def __repr__(self) -> str:
        return f"Item({self.key!r})"


_EXTRA_KINDS = frozenset({"norm", "breach"})


def _bound(value: float) -> Fraction | None:
    if not math.isfinite(value):
        return None
    return Fraction(repr(float(value)))


def _range_words(low: float, high: float, unit: str) -> str:
    lo, hi = number_words(low), number_words(high)
    if low == high:
        return with_unit(lo, unit)
    joiner = " to " if low < 0 or high < 0 else "-"
    return with_unit(f"{lo}{joiner}{hi}", unit)


def _interval_formula(
    quantity: str, spec: Quantity, low: float | None, high: float | None
) -> Callable[[Translator], str]:
    # A partial, not a closure: thousands of items each keep one (a closure's cells are
    # objects of their own that every garbage collection walks).
    return partial(_interval_text, quantity, low, high)


def _interval_text(quantity: str, low: float | None, high: float | None,
                   translator: Translator) -> str:
    symbol, kind = translator.quantity(quantity)
    parts: list[str] = []
    lo = _bound(low) if low is not None else None
    hi = _bound(high) if high is not None else None
    if kind == "boolean":
        if lo is not None and lo > 0:
            parts.append(symbol)
        if hi is not None and hi < 1:
            parts.append(f"(not {symbol})")
    elif kind == "integer":
        if lo is not None:
            parts.append(f"(<= {smt_int(math.ceil(lo))} {symbol})")
        if hi is not None:
            parts.append(f"(<= {symbol} {smt_int(math.floor(hi))})")
    else:
        if lo is not None:
            parts.append(f"(<= {smt_real(lo)} {symbol})")
        if hi is not None:
            parts.append(f"(<= {symbol} {smt_real(hi)})")
    if not parts:
        return "true"
    return parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})"


def expr_formula(expr: Expr, negate: bool = False) -> Callable[[Translator], str]:
    def build(translator: Translator) -> str:
        term = translator.condition(expr)
        return f"(not {term})" if negate else term

    return build


def _with_suffix(build: Callable[[Translator], str], suffix: str) -> Callable[[Translator], str]:
    if not suffix:
        return build

    def suffixed(translator: Translator) -> str:
        return build(translator.with_suffix(suffix))

    return suffixed
