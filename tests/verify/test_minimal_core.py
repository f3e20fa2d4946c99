"""Algorithm 1 (seed 001) returns a minimal core even when the core z3 hands it is padded with
statements that play no part (a shrink that kept the whole first half survived)."""

from __future__ import annotations

import itertools
import random

import pytest

from countersign.orders.model import Quantity
from countersign.verify.expressions import parse
from countersign.verify.logic import Item, Limits, Session, expr_formula

QUANTITIES = {name: Quantity() for name in ("x", "y", "z", "w")}


def _item(key: str, text: str) -> Item:
    return Item(key, "constraint", key, text, text, expr_formula(parse(text)))


# The contradiction needs three statements (x > 5, y > x, y < 4); the padding is satisfiable
# with any of them and with each other.
CORE = [_item("c1", "x > 5"), _item("c2", "y > x"), _item("c3", "y < 4")]
PADDING = [_item(f"p{i}", f"z >= {i} or w <= {i}") for i in range(9)]


def _session() -> Session:
    return Session(QUANTITIES, Limits.start(per_call_ms=10_000, total_s=120))


@pytest.mark.parametrize("seed", range(12))
def test_padded_cores_shrink_to_exactly_the_contradiction(seed: int) -> None:
    items = CORE + PADDING
    random.Random(seed).shuffle(items)
    session = _session()
    with session.scope(items):
        assert session.check(items).status == "unsat"
        found, proven = session.minimal_core(items)
        assert proven
        assert {i.key for i in found} == {"c1", "c2", "c3"}, [i.key for i in found]
        # Minimal: dropping any one statement of the result makes it satisfiable.
        for drop in found:
            assert session.check([i for i in found if i is not drop]).status == "sat"


def test_every_placement_of_the_contradiction_in_the_halves_is_minimal() -> None:
    """The contradiction split across the first and second half in every way, with padding
    in the first half (where a shrink that keeps the first half would keep it)."""
    session = _session()
    items_all = CORE + PADDING
    with session.scope(items_all):
        for positions in itertools.permutations(range(len(items_all)), 3):
            if positions[0] > 5:
                continue
            order = list(PADDING)
            for index, core_item in sorted(zip(positions, CORE, strict=True)):
                order.insert(min(index, len(order)), core_item)
            found, _ = session.minimal_core(order)
            assert len(found) == 3, ([i.key for i in order], [i.key for i in found])


# Two contradictions that cross the halves: {x > 5, x < 3} and {y > 5, y < 3}. Minimising the
# second half against the whole first half (instead of its minimised part) can keep a
# statement of the other contradiction and return a set that is not even a core.
CROSSING = [_item("a1", "x > 5"), _item("b1", "y > 5"), _item("a2", "x < 3"),
            _item("b2", "y < 3")]


@pytest.mark.parametrize("order", list(itertools.permutations(range(4))))
def test_a_second_half_is_minimised_against_the_minimised_first_half(
    order: tuple[int, ...],
) -> None:
    items = [CROSSING[i] for i in order]
    session = _session()
    with session.scope(items):
        found, proven = session.minimal_core(items)
        assert proven
        keys = {i.key for i in found}
        assert keys in ({"a1", "a2"}, {"b1", "b2"}), [i.key for i in items]
        assert session.check(found).status == "unsat"
