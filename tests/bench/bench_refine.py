"""Refinement: counting the refined exemplar's paths by dynamic programming over its
flat unrolling beside enumerating them with the brute force of tests/verify/refine_brute.py, as
the time-out grows. Prints times and their ratio (same process, same machine); never asserts.

    .venv/bin/python -m tests.bench.bench_refine
"""

from __future__ import annotations

import json
import time

from countersign.orders.examples import example_bytes
from countersign.orders.model import Orders
from countersign.orders.reader import read_json
from countersign.verify.paths import count_paths
from countersign.verify.refine import checked_form
from tests.verify.refine_brute import runs


def _orders(steps: int) -> Orders:
    data = json.loads(example_bytes("search-and-sample-refined"))
    data["goals"][0]["refines"]["within"] = {"steps": steps}
    return read_json(json.dumps(data).encode())


def main() -> None:
    print(f"{'steps':>5} {'paths':>10} {'flat goals':>10} {'DP s':>8} {'brute s':>8} {'ratio':>8}")
    for steps in (2, 4, 8, 12, 14):
        orders = _orders(steps)
        began = time.perf_counter()
        flat, graph = checked_form(orders)
        counts = count_paths(graph)
        dp = time.perf_counter() - began
        assert counts is not None
        began = time.perf_counter()
        enumerated = sum(1 for _ in runs(orders))
        brute = time.perf_counter() - began
        assert enumerated == counts.total
        print(f"{steps:>5} {counts.total:>10,} {len(flat.goals):>10} {dp:>8.4f} {brute:>8.3f} "
              f"{brute / dp:>8.1f}x")


if __name__ == "__main__":
    main()
