"""The validation report: every check that exists, run on one set of orders.

One pure function, so the command line, the API and the tests share a code path: the contingency
rules' design checks (RULES) run here too, so there is no second entry point to choose.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ..orders.canonical import digest
from ..orders.defaults import defaulted_findings
from ..orders.findings import Finding
from ..orders.model import Orders
from .budget import WorstPath, check_budget, worst_paths
from .geo import check_geo
from .graph import MissionGraph, build_graph
from .legs import mission_legs
from .logic import LogicCache, check_logic
from .meo import MeoResult, meo_check
from .paths import PathCounts, count_paths
from .patterns import check_patterns
from .probability import Probabilities, declares_probabilities, outcome_probabilities
from .properties import check_properties
from .rules_design import rules_findings
from .structure import check_structure
from .text import check_text
from .vehicle import check_vehicle

# The MEO route re-derives the structural verdicts too (tests prove both routes agree); the
# report takes from it only the rules no other check covers.
MEO_ONLY_CODES = frozenset({"C1", "C2", "M6", "M7"})

# Solver results are pure functions of their inputs, so one bounded cache serves every caller
# in the process: re-validating after a one-goal edit solves only what that goal touches.
SHARED_LOGIC_CACHE = LogicCache(max_entries=20_000)

# The solver time one validation may spend, shared by the logic and the property checks (issue
# 15: 40 nonlinear constraints and 20 path properties ran 76 s). What the solver cannot decide
# within it is a warning (CONTRADICTION, PROPERTY, VACUOUS), never an error nor a hang.
SOLVER_BUDGET_S = 8.0
SOLVER_CALL_MS = 1_000  # one solver call; a hard call gives up early and leaves the rest time


@dataclass(frozen=True)
class Report:
    mission: str
    digest: str
    findings: list[Finding]
    paths: PathCounts | None
    costs: dict[str, WorstPath] | None
    meo: MeoResult | None = field(default=None, repr=False, compare=False)
    # Outcome probabilities (issue 20), only for orders that declare some.
    probabilities: Probabilities | None = None

    @property
    def explanation(self) -> dict[str, Any] | None:
        """Why: the inferred MEO facts that matter (includes, canIdentify, hasCapability, ...),
        derived only when someone asks."""
        return self.meo.explanation if self.meo is not None else None

    @property
    def ok(self) -> bool:
        return not any(f.severity == "error" for f in self.findings)

    def to_json(self, explain: bool = False) -> dict[str, Any]:
        data = {
            "mission": self.mission,
            "digest": self.digest,
            "ok": self.ok,
            "findings": [f.to_json() for f in self.findings],
            "paths": self.paths.to_json() if self.paths else None,
            "costs": {q: w.to_json() for q, w in self.costs.items()} if self.costs else None,
        }
        if self.probabilities is not None:
            data["probabilities"] = self.probabilities.to_json()
        if explain:
            data["explanation"] = self.explanation
        return data


def validate(
    orders: Orders,
    reader_findings: Sequence[Finding] = (),
    graph: MissionGraph | None = None,
    logic_cache: LogicCache | None = None,
    *,
    solver_budget_s: float = SOLVER_BUDGET_S,
) -> Report:
    graph = graph or build_graph(orders)
    cache = logic_cache if logic_cache is not None else SHARED_LOGIC_CACHE
    findings = list(reader_findings)
    # Warnings an importer recorded in the orders (NPS default handlers) stay in every report;
    # the reader returns them too, so those already given are not repeated.
    given = {(f.code, f.subjects, f.message) for f in findings}
    findings.extend(f for f in defaulted_findings(orders)
                    if (f.code, f.subjects, f.message) not in given)
    findings.extend(check_structure(orders, graph))
    counts = count_paths(graph)
    legs = mission_legs(orders)
    costs = worst_paths(orders, graph, legs) if counts is not None else None
    findings.extend(check_budget(costs))
    meo = meo_check(orders)
    findings.extend(f for f in meo.findings if f.code in MEO_ONLY_CODES)
    findings.extend(check_vehicle(orders))
    findings.extend(check_text(orders))
    findings.extend(check_geo(orders, graph, legs))
    deadline = time.monotonic() + solver_budget_s
    findings.extend(check_logic(orders, cache, timeout_ms=SOLVER_CALL_MS,
                                total_timeout_s=solver_budget_s))
    findings.extend(check_properties(orders, graph, cache, timeout_ms=SOLVER_CALL_MS,
                                     total_timeout_s=max(0.0, deadline - time.monotonic())))
    findings.extend(rules_findings(orders))
    findings.extend(check_patterns(orders, graph))
    probabilities = (outcome_probabilities(orders, graph)
                     if counts is not None and declares_probabilities(orders) else None)
    return Report(orders.id, digest(orders), findings, counts, costs, meo, probabilities)
