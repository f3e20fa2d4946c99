"""Turtle readers and writers stay linear in their input (issues 15 and 22)."""

from __future__ import annotations

import pytest

from countersign.orders import turtle
from countersign.orders.model import Orders
from countersign.orders.reader import OrdersReadError
from countersign.orders.turtle import read_turtle, write_turtle

HEAD = (b"@prefix cs: <https://countersign.example/ontology/orders#> .\n"
        b"@prefix meo: <https://countersign.example/ontology/meo#> .\n"
        b"@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .\n"
        b"<https://countersign.example/mission/m> a meo:Mission ; cs:id \"m\" ;\n")


def shared_lists(depth: int) -> bytes:
    """List k holds list k-1 twice: a few hundred statements that expand to 2^depth values."""
    lines = [b'_:l0 rdf:first "x" ; rdf:rest rdf:nil .']
    for k in range(1, depth + 1):
        lines.append(
            f"_:l{k} rdf:first _:l{k - 1} ; rdf:rest _:r{k} .\n"
            f"_:r{k} rdf:first _:l{k - 1} ; rdf:rest rdf:nil .".encode()
        )
    return HEAD + f"  cs:params _:l{depth} .\n".encode() + b"\n".join(lines) + b"\n"


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
