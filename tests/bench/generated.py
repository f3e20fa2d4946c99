"""Generated orders for benchmarks: large random ternary DAGs with costs and a budget, and the
checks every benchmark runs on its input before timing it (a benchmark of an invalid
mission measures the wrong work)."""

from __future__ import annotations

import random
from collections.abc import Iterable

from countersign.orders.model import OUTCOMES, Orders

# A vehicle profile the VEHICLE check accepts: it states what the vehicle can do.
VEHICLE: dict[str, object] = {
    "id": "v", "title": "Bench vehicle", "envelope": {"depth_m": [0, 300], "speed_mps": [0, 3]},
    "budget": {"energy_wh": 10**9, "duration_s": 10**12},
}


def checked(orders: Orders, expected: Iterable[str] = ()) -> Orders:
    """The orders, refused (SystemExit naming the findings) unless `validate` reports no error
    beyond the codes the benchmark means to produce."""
    from countersign.verify import validate

    allowed = set(expected)
    report = validate(orders)
    errors = [f"{f.code}: {f.message[:120]}" for f in report.findings
              if f.severity == "error" and f.code not in allowed]
    if errors:
        raise SystemExit(f"benchmark input {orders.id} is invalid: " + "; ".join(errors[:5]))
    return orders


def checked_structure(orders: Orders) -> Orders:
    """The orders, refused unless the structural check passes: for inputs whose logic findings
    are what a benchmark measures (validating those in full would time the benchmark twice)."""
    from countersign.verify.structure import check_structure

    errors = [f"{f.code}: {f.message[:120]}" for f in check_structure(orders)
              if f.severity == "error"]
    if errors:
        raise SystemExit(f"benchmark input {orders.id} is invalid: " + "; ".join(errors[:5]))
    return orders


def random_dag(goals: int, seed: int = 7, reach: int = 12) -> Orders:
    """Each goal's outcomes name goals at most `reach` places later (or a terminal), and every
    goal is reachable because the succeed outcome always names the very next goal."""
    rng = random.Random(seed)
    items = []
    for i in range(goals):
        nxt: dict[str, str] = {}
        for k, outcome in enumerate(OUTCOMES):
            if i + 1 >= goals:
                nxt[outcome] = "COMPLETE" if k == 0 else "ABORT"
            elif k == 0:
                nxt[outcome] = f"G{i + 1}"
            else:
                hop = rng.randint(1, reach)
                nxt[outcome] = f"G{i + hop}" if i + hop < goals else "ABORT"
        items.append({
            "id": f"G{i}", "title": f"Goal {i}", "next": nxt,
            "cost": {"energy_wh": rng.randint(1, 50), "duration_s": rng.randint(60, 3600)},
        })
    return Orders.model_validate({
        "id": f"dag-{goals}", "start": "G0", "vehicle": "v", "goals": items,
        "vehicles": [VEHICLE],
    })


def layered_dag(depth: int) -> Orders:
    """A chain where succeed and fail go to the next goal and violate aborts: 2^depth paths
    that all reach the end, for streaming benchmarks."""
    items = []
    for i in range(depth):
        following = f"G{i + 1}" if i + 1 < depth else "COMPLETE"
        items.append({"id": f"G{i}", "next": {"succeed": following, "fail": following,
                                               "violate": "ABORT"}})
    return Orders.model_validate({"id": f"chain-{depth}", "start": "G0", "goals": items})


TURTLE_HEAD = (b"@prefix cs: <https://countersign.example/ontology/orders#> .\n"
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
    return TURTLE_HEAD + f"  cs:params _:l{depth} .\n".encode() + b"\n".join(lines) + b"\n"
