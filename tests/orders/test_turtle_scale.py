"""Turtle readers and writers stay linear in their input."""

from __future__ import annotations

from pathlib import Path

import pytest

from countersign.orders.canonical import digest
from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.orders.reader import OrdersReadError
from countersign.orders.turtle import read_turtle, write_turtle
from countersign.orders.turtle import reader as turtle
from tests.bench.generated import random_dag, shared_lists


def test_nested_shared_lists_are_refused_after_linear_work(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    calls = 0
    decode = turtle._Reader.decode

    def counting(self: turtle._Reader, node: object, depth: int = 0) -> object:
        nonlocal calls
        calls += 1
        return decode(self, node, depth)  # type: ignore[arg-type]

    monkeypatch.setattr(turtle._Reader, "decode", counting)
    document = shared_lists(18)
    with pytest.raises(OrdersReadError, match="expand"):
        read_turtle(document)
    statements = len(turtle._parse(document, "x"))
    # Linear: bounded by the statements, not by the 2^18 values the sharing would expand to.
    assert calls <= turtle.DECODE_FACTOR * statements + turtle.DECODE_SLACK + 1
    assert calls < 2**18


def test_shallow_shared_lists_are_still_read() -> None:
    orders = read_turtle(shared_lists(3)).orders
    assert orders.id == "m"


def test_literals_with_every_line_separator_and_escape_read_back() -> None:
    # The Turtle reader splits Oxigraph's N-Triples at "\n" only; these characters are line
    # boundaries for str.splitlines() and are written unescaped inside literals.
    tricky = 'a\u2028b\x85c\x0bd\x1ce\u2029f "quoted" back\\slash\ttab\nnewline \U0001F600'
    orders = Orders.model_validate({
        "id": "tricky", "title": tricky, "description": tricky, "start": "G1",
        "goals": [{"id": "G1", "title": tricky,
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
    })
    assert read_turtle(write_turtle(orders).encode()).orders == orders


LEGACY = Path(__file__).with_name("data") / "legacy-record-search-and-sample.ttl"


def test_record_maps_are_compact() -> None:
    # Maps whose keys are names are written as key: properties, one statement per entry;
    # the cs:entry form took three statements per entry and one for the map's type.
    orders = random_dag(200, seed=3)
    statements = len(turtle._parse(write_turtle(orders).encode(), "x"))
    assert statements <= 17 * 200 + 50
    assert "cs:entry" not in write_turtle(orders)


def test_a_map_with_keys_that_are_not_names_keeps_the_entry_form() -> None:
    orders = Orders.model_validate({
        "id": "keys", "start": "G1",
        "goals": [{"id": "G1", "params": {"two words": 1, "inner": {"ok": [1, {}, {"x.y": 2}]}},
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
    })
    text = write_turtle(orders)
    assert "cs:entry" in text and "key:ok" in text
    assert read_turtle(text.encode()).orders == orders


def test_turtle_written_with_the_entry_form_for_every_map_still_reads_back() -> None:
    # Written by the writer before the compact form (commit d60e3cc) from the example.
    back = read_turtle(LEGACY.read_bytes()).orders
    assert digest(back) == digest(load_example("search-and-sample"))


def test_the_text_writer_states_what_the_graph_states() -> None:
    # write_turtle renders text straight from the orders; its statements must be those of
    # orders_to_graph (the route verification and the NPS view use), blank nodes aside.
    from rdflib import Graph
    from rdflib.compare import isomorphic

    from countersign.orders.examples import example_names, load_example
    from tests.bench.bench_logic import logic_orders
    from tests.turtle_via_graph import write_turtle_via_graph

    for orders in [*(load_example(n) for n in example_names()),
                   logic_orders(goals=40, constraints=12, norms=5)]:
        text = Graph().parse(data=write_turtle(orders), format="turtle")
        graph = Graph().parse(data=write_turtle_via_graph(orders), format="turtle")
        assert isomorphic(text, graph), orders.id


@pytest.mark.parametrize("seed", [11, 12, 13])
def test_the_benchmark_mission_round_trips_by_digest(seed: int) -> None:
    # The richer mission of the Turtle benchmark: envelopes, costs, norms, areas, scoped
    # constraints and properties.


    from tests.bench.bench_logic import logic_orders

    orders = logic_orders(goals=300, constraints=40, norms=10, seed=seed)
    assert digest(read_turtle(write_turtle(orders).encode()).orders) == digest(orders)


def test_a_json_list_of_the_record_that_is_not_scalars_is_a_read_error() -> None:
    text = write_turtle(random_dag(3, seed=1)).replace(
        '"[', '"[{\\"x\\": 1}, ', 1)
    assert '^^rdf:JSON' in text
    with pytest.raises(OrdersReadError):
        read_turtle(text.encode())
