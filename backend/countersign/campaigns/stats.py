"""What a campaign's simulations estimate: each terminal's probability and that of any
violation with Wilson score intervals, each goal's outcome probabilities (offered to fill the
orders' `p`, item 1), the paths covered (numbered as `countersign paths`) and an energy
histogram.

Wilson's interval (Wilson 1927; Newcombe 1998 recommends it over the Wald interval) is closed
form, so no statistics library is needed; it stays inside [0, 1] and is sensible at 0 and n.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Sequence
from typing import Any

from ..orders.model import OUTCOMES
from ..verify.refine import base_id

Z_95 = 1.959963984540054  # the standard normal's 0.975 quantile
HISTOGRAM_BINS = 20
FORMAT = "countersign.campaign/1"


def wilson(successes: int, trials: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval for a binomial proportion."""
    if trials <= 0:
        return (0.0, 1.0)
    if not 0 <= successes <= trials:
        raise ValueError(f"successes must be between 0 and {trials}, not {successes}")
    p = successes / trials
    z2 = z * z
    centre = (p + z2 / (2 * trials)) / (1 + z2 / trials)
    half = z / (1 + z2 / trials) * math.sqrt(p * (1 - p) / trials + z2 / (4 * trials * trials))
    return (max(0.0, centre - half), min(1.0, centre + half))


def estimate(count: int, trials: int) -> dict[str, Any]:
    low, high = wilson(count, trials)
    return {"count": count, "p": count / trials if trials else None,
            "ci": [round(low, 6), round(high, 6)]}


def histogram(values: Sequence[float], bins: int = HISTOGRAM_BINS) -> dict[str, Any]:
    if not values:
        return {"edges": [], "counts": []}
    low, high = min(values), max(values)
    if high - low < 1e-9:
        return {"edges": [round(low, 3), round(low + 1.0, 3)], "counts": [len(values)]}
    width = (high - low) / bins
    counts = [0] * bins
    for value in values:
        counts[min(bins - 1, int((value - low) / width))] += 1
    return {"edges": [round(low + i * width, 3) for i in range(bins + 1)], "counts": counts}


def summarize(runs: Iterable[dict[str, Any]], *, total_paths: int | None,
              terminals: Sequence[tuple[str, str]], goals: Sequence[str]) -> dict[str, Any]:
    """The estimates over the simulations (one result per index: the caller's guarantee).
    `terminals` are (id, kind) pairs, `goals` the orders' goal ids in order."""
    runs = list(runs)
    n = len(runs)
    ending: Counter[str] = Counter()
    visits: dict[str, Counter[str]] = {g: Counter() for g in goals}
    paths: Counter[int] = Counter()
    violated = unfinished = 0
    energy: list[float] = []
    for run in runs:
        ending[run.get("terminal") or "none"] += 1
        outcomes = run.get("outcomes", [])
        violated += "violate" in outcomes
        unfinished += not run.get("terminal")
        for goal, outcome in zip(run.get("goals", []), outcomes, strict=False):
            # A refined mission's copies (G1/G1.2#3) are one goal of the orders, one `p`.
            visits.setdefault(base_id(goal), Counter())[outcome] += 1
        if run.get("path") is not None:
            paths[int(run["path"])] += 1
        energy.append(float(run.get("energy_wh", 0.0)))
    by_kind: Counter[str] = Counter()
    kinds = dict(terminals)
    for terminal, count in ending.items():
        by_kind[kinds.get(terminal, "none")] += count
    goal_estimates = {}
    for goal, counter in visits.items():
        total = sum(counter.values())
        goal_estimates[goal] = {"visits": total,
                                **{o: estimate(counter[o], total) for o in OUTCOMES}}
    return {
        "simulations": n,
        "terminals": {t: estimate(ending[t], n) for t, _ in terminals},
        "kinds": {k: estimate(by_kind[k], n) for k in ("complete", "abort")},
        "no_terminal": estimate(unfinished, n),
        "any_violation": estimate(violated, n),
        "goals": goal_estimates,
        "coverage": {"total_paths": total_paths, "covered": len(paths),
                     "paths": [{"path": p, "count": c} for p, c in sorted(paths.items())]},
        "energy_wh": {
            "mean": round(sum(energy) / n, 3) if n else None,
            "min": round(min(energy), 3) if energy else None,
            "max": round(max(energy), 3) if energy else None,
            "histogram": histogram(energy),
        },
    }


def goal_probabilities(summary: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Per goal visited at least once, `p` in the orders' form, two ways for the operator to
    choose: the point estimates (normalised to sum to 1) and the 95% intervals. Wilson
    intervals contain the point estimate, so the intervals always admit a sum of 1."""
    offered: dict[str, dict[str, Any]] = {}
    for goal, data in summary["goals"].items():
        visits = data["visits"]
        if not visits:
            continue
        point = {o: round(data[o]["count"] / visits, 4) for o in OUTCOMES}
        # Rounding may leave the sum a hair off 1: put the remainder on the largest.
        largest = max(OUTCOMES, key=lambda o: point[o])
        point[largest] = round(point[largest] + 1.0 - sum(point.values()), 4)
        interval = {o: [math.floor(data[o]["ci"][0] * 1e4) / 1e4,
                        math.ceil(data[o]["ci"][1] * 1e4) / 1e4] for o in OUTCOMES}
        offered[goal] = {"visits": visits, "point": point, "interval": interval}
    return offered
