"""MEO validation benchmark. Run: .venv/bin/python -m tests.bench.bench_meo

Prints, for the exemplar and generated missions of 100 and 1,000 goals, the time of
`meo_check` (staged reasoning + closed-world rules) next to baselines measured in this same run:
a naive owlrl closure of meo.ttl plus the whole mission (the textbook route; run up to
`--naive-max` goals because it grows about n^3: DESIGN.md measured 263 s at 400 goals), pySHACL
on the same data graph, and HermiT through owlready2 when owlready2 and Java are present.
"""

from __future__ import annotations

import argparse
import gc
import random
import shutil
import tempfile
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from typing import Any

import owlrl
from rdflib import Graph

from countersign.ontology_files import MEO as MEO_FILE
from countersign.orders.examples import load_example
from countersign.orders.model import OUTCOMES, Orders
from countersign.orders.ontology import load_graph
from countersign.orders.turtle import orders_to_graph
from countersign.verify import validate
from countersign.verify.meo.reasoning import infer
from tests.bench.timing import best_of
from tests.oracles.meo_route import meo_check
from tests.oracles.meo_shapes import shacl_violations, validation_graph

REQUIREMENTS = ("transit", "area_search", "sample", "rendezvous")


def naive_closure(graph: Graph) -> Graph:
    """The textbook route: owlrl's OWL 2 RL closure of all of meo.ttl and every triple.
    Quadratic or worse in goals; the oracle of tests/verify/test_meo.py on small orders and the
    baseline here."""
    closed = Graph()
    for triple in load_graph(MEO_FILE):
        closed.add(triple)
    for triple in graph:
        closed.add(triple)
    owlrl.DeductiveClosure(
        owlrl.OWLRL_Semantics, axiomatic_triples=False, datatype_axioms=False
    ).expand(closed)
    return closed


def meo_mission(goals: int, seed: int = 3) -> Orders:
    """A valid mission of `goals` goals: forward successors (a DAG where every goal is reached),
    requirements from a small vocabulary, three mission-wide constraints and one goal-scoped
    constraint per ten goals, and a vehicle whose features cover everything."""
    rng = random.Random(seed)
    items: list[dict[str, Any]] = []
    for i in range(goals):
        nxt: dict[str, str] = {}
        for k, outcome in enumerate(OUTCOMES):
            if i + 1 >= goals:
                nxt[outcome] = "COMPLETE" if k == 0 else "ABORT"
            elif k == 0:
                nxt[outcome] = f"G{i + 1}"
            else:
                hop = rng.randint(1, 12)
                nxt[outcome] = f"G{i + hop}" if i + hop < goals else "ABORT"
        items.append({"id": f"G{i}", "title": f"Goal {i}", "next": nxt,
                      "requires": [rng.choice(REQUIREMENTS)]})
    constraints: list[dict[str, Any]] = [
        {"id": "nav", "applies_to": "mission", "expr": "nav_error_m <= 10"},
        {"id": "depth", "applies_to": "mission", "expr": "depth_m >= 20"},
        {"id": "health", "applies_to": "mission", "expr": "systems_ok"},
    ]
    for j in range(0, goals, 10):
        window = [f"G{k}" for k in range(j, min(goals, j + 4))]
        constraints.append({"id": f"lane{j}", "applies_to": window,
                            "expr": "lane_distance_m >= 1000 or depth_m >= 20"})
    return Orders.model_validate({
        "id": f"meo-{goals}", "start": "G0", "vehicle": "auv", "goals": items,
        "constraints": constraints,
        # systems_ok is a condition, not a number (undeclared quantities are real).
        "quantities": {"systems_ok": {"type": "boolean"}},
        "vehicles": [{"id": "auv", "features": [
            {"id": "nav", "fulfills": ["transit", "rendezvous"],
             "measures": ["nav_error_m", "depth_m", "lane_distance_m"]},
            {"id": "sonar", "fulfills": ["area_search"], "measures": ["depth_m"]},
            {"id": "sampler", "fulfills": ["sample"]},
            {"id": "health", "measures": ["systems_ok"]},
        ]}],
    })


def checked(orders: Orders) -> Orders:
    """The benchmark's input, refused unless it validates without errors: timing an invalid
    mission measures the wrong work."""
    report = validate(orders)
    errors = [f"{f.code}: {f.message}" for f in report.findings if f.severity == "error"]
    if errors:
        raise SystemExit(f"benchmark input {orders.id} is invalid: " + "; ".join(errors[:5]))
    return orders



def peak_mib(action: Callable[[], object]) -> float:
    gc.collect()
    tracemalloc.start()
    action()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / 2**20


def hermit_available() -> str | None:
    """None when HermiT can run, else why not."""
    try:
        import owlready2  # noqa: F401
    except ImportError:
        return "owlready2 is not installed (pip install -e '.[dl]')"
    if shutil.which("java") is None:
        return "Java is not installed (HermiT runs on the JVM)"
    return None


def hermit_seconds(orders: Orders | None) -> float:
    """Load meo.ttl (plus the mission) into owlready2 and run HermiT; seconds for the reasoner."""
    import owlready2
    from rdflib import Graph

    from countersign.ontology_files import MEO

    graph = Graph()
    for triple in load_graph(MEO):
        graph.add(triple)
    if orders is not None:
        for triple in orders_to_graph(orders, record=False):
            graph.add(triple)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "meo.nt"
        path.write_text(graph.serialize(format="nt"), encoding="utf-8")
        world = owlready2.World()
        world.get_ontology(path.as_uri()).load(format="ntriples")
        start = time.perf_counter()
        with world.get_ontology("http://countersign.example/inferred"):
            owlready2.sync_reasoner_hermit(world, infer_property_values=False, debug=0)
        return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--naive-max", type=int, default=100,
                        help="largest mission for the naive owlrl baseline (default 100 goals)")
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()

    cases: list[tuple[str, Orders, float]] = [
        ("exemplar (5 goals)", checked(load_example("search-and-sample")), 0.100),
        ("100 goals", checked(meo_mission(100)), 0.300),
        ("1,000 goals", checked(meo_mission(1000)), 3.0),
    ]
    why_no_hermit = hermit_available()
    print("## MEO validation: meo_check (staged OWL-RL + closed-world shapes)")
    print(f"{'mission':<20} {'triples':>7} {'ours ms':>8} {'budget':>7} {'peak MiB':>9} "
          f"{'naive owlrl':>14} {'ratio':>7} {'pySHACL':>10} {'HermiT':>10}")
    for label, orders, budget in cases:
        triples = len(orders_to_graph(orders, record=False))
        meo_check(orders)  # warm caches (ontology files, parsed shapes)
        runs = args.runs if len(orders.goals) < 1000 else max(2, args.runs // 2)
        ours = best_of(runs, lambda o=orders: meo_check(o))
        peak = peak_mib(lambda o=orders: meo_check(o))
        if len(orders.goals) <= args.naive_max:
            graph = orders_to_graph(orders, record=False)
            naive = best_of(1, lambda g=graph: naive_closure(g))
            naive_text, ratio = f"{naive * 1000:11.0f} ms", f"{naive / ours:6.0f}x"
        else:
            naive_text, ratio = f"not run (>{args.naive_max})", "-"
        if len(orders.goals) <= 100:
            graph = orders_to_graph(orders, record=False)
            data = validation_graph(graph, infer(graph))
            shacl = best_of(1, lambda d=data: shacl_violations(d))
            shacl_text = f"{shacl * 1000:7.0f} ms"
        else:
            shacl_text = "not run"
        if why_no_hermit is None and len(orders.goals) <= 100:
            hermit_text = f"{hermit_seconds(orders) * 1000:7.0f} ms"
        else:
            hermit_text = "skipped"
        verdict = "ok" if ours <= budget else "OVER"
        print(f"{label:<20} {triples:>7} {ours * 1000:8.1f} {budget * 1000:5.0f}{verdict:>2} "
              f"{peak:9.1f} {naive_text:>14} {ratio:>7} {shacl_text:>10} {hermit_text:>10}")
    if why_no_hermit is not None:
        print(f"HermiT skipped: {why_no_hermit}")
    print("naive owlrl = owlrl OWL-RL closure of meo.ttl and every triple of the mission; "
          "pySHACL = shapes.ttl on the same data graph as ours; HermiT = owlready2 "
          "consistency of meo.ttl and the mission (reasoner time only).")


if __name__ == "__main__":
    main()
