"""Turtle read time against nesting depth: linear in the document, not in what
shared blank-node lists would expand to.

Each document holds lists where list k contains list k-1 twice, so depth d is about 4d
statements that a naive decoder expands into 2^d values (depth 18 took 41 s before the fix).
Beside our reader (which refuses the document once the expansion passes a bound linear in its
statements) is rdflib's own Turtle parser on the same bytes, a reader that only parses. Our
time must stay bounded as the depth grows, while the naive expansion doubles with each level.

Run: .venv/bin/python -m tests.bench.bench_turtle_depth
"""

from __future__ import annotations

import contextlib
from functools import partial

from rdflib import Graph

from countersign.orders.reader import OrdersReadError
from countersign.orders.turtle import read_turtle
from tests.bench.generated import shared_lists
from tests.bench.timing import best_of

RUNS = 5

DEPTHS = (8, 12, 14, 16, 18, 24, 32, 64)


def ours(document: bytes) -> None:
    with contextlib.suppress(OrdersReadError):  # refused: the expansion passed the bound
        read_turtle(document)


def rdflib_parse(document: bytes) -> None:
    Graph().parse(data=document, format="turtle")


def main() -> None:
    print(f"{'depth':>6} {'bytes':>7} {'naive values':>13} {'ours ms':>9} "
          f"{'rdflib parse ms':>16}")
    mine: dict[int, float] = {}
    for depth in DEPTHS:
        document = shared_lists(depth)
        mine[depth] = best_of(RUNS, partial(ours, document))
        parse = best_of(RUNS, partial(rdflib_parse, document))
        print(f"{depth:>6} {len(document):>7} {2 ** depth:>13.3g} {mine[depth] * 1e3:>9.1f} "
              f"{parse * 1e3:>16.1f}")
    growth = mine[32] / mine[12]
    print(f"ours at depth 32 / depth 12: {growth:.2f}x while a naive decoder's work grows "
          f"{2 ** 20:,}x ({'PASS' if growth < 4 else 'MISS'}: bounded by the statements; "
          "past depth 64 the nesting bound refuses at once)")


if __name__ == "__main__":
    main()
