"""Naive baselines, run in the same process as the real code so ratios compare like with like.

`naive_paths` explores outcome sequences the way a simple mission engine does: recursively,
materialising each path, guarding only against revisiting a goal on the current path.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator

from countersign.orders.model import OUTCOMES, Orders


class TimeUp(Exception):
    pass


def naive_paths(orders: Orders, deadline: float | None = None) -> Iterator[dict[str, object]]:
    goals = {g.id: g for g in orders.goals}
    terminals = {t.id for t in orders.effective_terminals}
    counter = 0

    def visit(gid: str, trail: list[str], outs: list[str]) -> Iterator[dict[str, object]]:
        nonlocal counter
        counter += 1
        if deadline is not None and counter % 1000 == 0 and time.perf_counter() > deadline:
            raise TimeUp
        for outcome in OUTCOMES:
            target = goals[gid].successors(outcome)
            if not target:
                continue
            nxt = target[0]
            if nxt in terminals or nxt not in goals:
                yield {"goals": [*trail, gid], "outcomes": [*outs, outcome], "terminal": nxt}
            elif nxt not in trail and nxt != gid:
                yield from visit(nxt, [*trail, gid], [*outs, outcome])

    yield from visit(str(orders.start), [], [])


def naive_ndjson(orders: Orders, limit: int) -> int:
    written = 0
    for index, path in enumerate(naive_paths(orders), 1):
        json.dumps({"index": index, **path})
        written += 1
        if written >= limit:
            break
    return written
