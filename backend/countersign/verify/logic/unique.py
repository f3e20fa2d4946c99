"""A unit's core without z3, when it is the only one there is.

Which minimal core z3 and the shrinking (session.minimal_core) end at is up to the solver when
a unit has several; when it has exactly one (counting identical twins once, as
`Session.earliest_twins` names them), every route ends at it. So a core M found here is
used only once it is proven to be that one: M cannot hold (bounds.py proves it), and the unit
without any one item of M can (bounds.py proves that too). Then every minimal core of the unit
holds all of M and, being minimal, is M. The candidates tried are a statement that the goal's
facts alone make false (a norm that forbids the goal's behaviour in its area's tags, a
constraint its behaviour and area break) with the fewest facts that do so; anything else, or
any answer bounds.py cannot prove, leaves the unit to z3 as before.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import filterfalse
from typing import Any

from .bounds import Decider
from .items import Item


class UniqueCores:
    """Unique cores of goal units, proven by one model's Decider."""

    def __init__(self, decider: Decider, order: dict[str, int]) -> None:
        self.decider = decider
        self._bases: dict[int, tuple[frozenset[Item], frozenset[Item]]] = {}
        self._without: dict[tuple[int, Item], frozenset[Item]] = {}
        self._base_keys: dict[int, set[Any]] = {}
        # Constraint key -> place in the orders (the order of the base in a unit's items).
        self._order = order
        self.found = 0

    def core(self, items: Sequence[Item], base: frozenset[Item]) -> list[Item] | None:
        """The unit's only minimal core (first twins named), or None when not proven so."""
        own = list(filterfalse(base.__contains__, items))
        if len(items) - len(own) != len(base):  # some of the base dropped: not tried here
            return None
        kept = self._first_base(base)
        own_firsts = self._first_twins(own, kept)
        firsts = [*own_firsts, *kept]
        culprit = self.decider.false_by_facts(firsts)
        if culprit is None:
            return None
        # The base holds constraints only: the facts, and the rest below, are the goal's own.
        facts = [i for i in own_firsts if i.meaning is not None and i.meaning[0] == "fact"]
        core = [culprit, *facts]
        status = self.decider.status
        if status(core, frozenset()) != "unsat":
            return None
        for fact in facts:
            fewer = [i for i in core if i is not fact]
            if status(fewer, frozenset()) == "unsat":
                core = fewer
        for item in core:
            without = self._base_without(kept, item) if item in kept else kept
            rest = [i for i in own_firsts if i is not item]
            if status(rest, without) != "sat":
                return None
        self.found += 1
        return core

    def _first_base(self, base: frozenset[Item]) -> frozenset[Item]:
        """The base's first twins. The base (the mission-wide constraints, in the orders'
        order) comes first among a unit's constraints, so they are the same for every unit:
        made once per base."""
        found = self._bases.get(id(base))
        if found is None or found[0] is not base:
            ordered = sorted(base, key=lambda i: self._order.get(i.key, len(self._order)))
            kept = frozenset(_dedupe(ordered, set()))
            self._bases[id(base)] = found = (base, kept)
        return found[1]

    def _first_twins(self, own: Sequence[Item], kept: frozenset[Item]) -> list[Item]:
        """The unit's own items, each twin after the first left out (the base's first twins,
        `kept`, come after them in the unit). Twins have one kind, and
        the base's constraints come before the goal's own, so the base's first twins stay and
        a goal's constraint that repeats one of them goes."""
        seen = self._base_keys.get(id(kept))
        if seen is None:
            seen = self._base_keys[id(kept)] = {_twin_key(i) for i in kept}
        return _dedupe(own, set(seen))

    def _base_without(self, kept: frozenset[Item], item: Item) -> frozenset[Item]:
        key = (id(kept), item)
        found = self._without.get(key)
        if found is None:
            found = self._without[key] = kept - {item}
        return found


def _twin_key(item: Item) -> Any:
    # Same kind and same meaning: the same formula (a coarser test than the session's, which
    # compares formula texts; a twin missed here only makes the core not proven unique).
    meaning = item.meaning
    if meaning is None:
        return item
    return item.kind, meaning[1] if meaning[0] == "expr" else meaning


def _dedupe(items: Sequence[Item], seen: set[Any]) -> list[Item]:
    out: list[Item] = []
    for item in items:
        key = _twin_key(item)
        if key not in seen:
            seen.add(key)
            out.append(item)
    return out
