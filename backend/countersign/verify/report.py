"""The validation report: every check that exists, run on one set of orders.

One pure function, so the command line, the API and the tests share a code path: the contingency
rules' design checks (RULES) run here too, so there is no second entry point to choose.

Incremental: the report is assembled from parts, each filed
in a `PartsCache` under the digest of exactly what its checks read (`verify.parts`). An edit
recomputes only the parts whose inputs it changed: a description edit none, a goal's cost the
structural part, a goal's title the structural, MEO and logic parts (the logic part then
re-solves only the units the goal touches, through the shared LogicCache). Tests compare
incremental reports with reports from scratch over random edits.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

from ..orders.canonical import digest
from ..orders.defaults import defaulted_findings
from ..orders.findings import Finding
from ..orders.model import Orders, declares_probabilities
from . import fingerprint
from .budget import WorstPath, check_budget, worst_paths
from .geo import check_geo
from .graph import MissionGraph, build_graph
from .legs import mission_legs
from .logic import THREAD_CLOCKS, Clocks, Limits, LogicCache, check_logic
from .meo.direct import meo_only_findings
from .parts import SHARED_PARTS, UNKEYED, PartKeys, PartsCache, part_keys
from .paths import PathCounts, count_paths
from .refine import Flat, dedupe_copies, flat_graph, flatten, has_refinements, refine_findings
from .rules_design import rules_findings
from .structure import check_structure
from .text import check_text
from .vehicle import check_vehicle

if TYPE_CHECKING:
    # The checks of what a mission may not have (path patterns, outcome probabilities,
    # procedures) load when it has them, the JSON document when asked for.
    from .meo.reasoned import MeoResult
    from .probability import Probabilities
    from .report_document import ReportDocument
    from .team_report import TeamSummary

# The MEO route re-derives the structural verdicts too (tests prove both routes agree); the
# report takes from it only the rules no other check covers (`meo.direct.CODES`), evaluated
# straight from the orders by `meo.direct` (tests prove it equal to the MEO route's findings).
# The MEO route itself runs when its explanation is asked for.

# Solver results are pure functions of their inputs, so one bounded cache serves every caller
# in the process: re-validating after a one-goal edit solves only what that goal touches.
SHARED_LOGIC_CACHE = LogicCache(max_entries=20_000)

# The solver time one validation may spend, shared by the logic and the property checks (40
# nonlinear constraints and 20 path properties once ran 76 s): CPU time of the work, so that a
# busy machine decides what a quiet one does, under a wall-clock cap (by default 4 times as
# long: logic/limits.py) that ends it in any case. What the solver cannot decide within them
# is a warning (CONTRADICTION, PROPERTY, VACUOUS), never an error nor a hang.
SOLVER_BUDGET_S = 8.0
SOLVER_CALL_MS = 1_000  # one solver call; a hard call gives up early and leaves the rest time


@dataclass(frozen=True)
class Report:
    mission: str
    digest: str
    findings: list[Finding]
    paths: PathCounts | None
    costs: dict[str, WorstPath] | None
    orders: Orders | None = field(default=None, repr=False, compare=False)
    # Outcome probabilities, only for orders that declare some.
    probabilities: Probabilities | None = None
    # Orders with a team: each member's figures and the joint counts (verify/team_report.py).
    team: TeamSummary | None = None

    @cached_property
    def meo(self) -> MeoResult | None:
        """The MEO reasoning (graph, inference, explanation), run when first asked for."""
        from .meo.reasoned import meo_reasoning  # rdflib and owlrl: only for the explanation

        return meo_reasoning(self.orders) if self.orders is not None else None

    @property
    def explanation(self) -> dict[str, Any] | None:
        """Why: the inferred MEO facts that matter (includes, canIdentify, hasCapability, ...),
        derived only when someone asks."""
        return self.meo.explanation if self.meo is not None else None

    @property
    def ok(self) -> bool:
        return not any(f.severity == "error" for f in self.findings)

    def document(self, explain: bool = False) -> ReportDocument:
        """The report as its JSON document (verify/report_document.py)."""
        from .report_document import PathSummary, ReportDocument

        paths = self.paths
        return ReportDocument(
            mission=self.mission, digest=self.digest, ok=self.ok,
            findings=tuple(self.findings),
            paths=PathSummary(paths.total, dict(paths.by_terminal)) if paths else None,
            costs={q: w.to_json() for q, w in self.costs.items()} if self.costs else None,
            # Which checks made it: the store keys reports by it and recomputes any other.
            checker=fingerprint.checker_fingerprint(),
            probabilities=(self.probabilities.to_json() if self.probabilities is not None
                           else None),
            team=self.team.to_json() if self.team is not None else None,
            explanation=self.explanation if explain else None, explained=explain)

    def to_json(self, explain: bool = False) -> dict[str, Any]:
        return self.document(explain).to_json()


def validate(
    orders: Orders,
    reader_findings: Sequence[Finding] = (),
    graph: MissionGraph | None = None,
    logic_cache: LogicCache | None = None,
    *,
    solver_budget_s: float = SOLVER_BUDGET_S,
    solver_wall_cap_s: float | None = None,
    solver_clocks: Clocks = THREAD_CLOCKS,
    parts: PartsCache | None = None,
    keys: PartKeys | None = None,
    orders_digest: str | None = None,
) -> Report:
    """Every check on the orders. `parts` (default: one cache shared by the process) holds
    the report parts of earlier validations by the digest of what they read; pass a fresh
    PartsCache to validate from scratch (a NoParts: from scratch, keeping nothing). `keys` and
    `orders_digest`, when the caller computed them already, save computing them again. The
    solver may spend `solver_budget_s` seconds of this thread's CPU time and stops at
    `solver_wall_cap_s` of wall time (default: 4 times the budget) in any case;
    `solver_clocks` are where both are read."""
    if orders.team is not None:
        from .team_report import validate_team

        return validate_team(orders, reader_findings, logic_cache,
                             solver_budget_s=solver_budget_s,
                             solver_wall_cap_s=solver_wall_cap_s, solver_clocks=solver_clocks,
                             parts=parts, orders_digest=orders_digest)
    cache = logic_cache if logic_cache is not None else SHARED_LOGIC_CACHE
    store = parts if parts is not None else SHARED_PARTS
    if keys is None:
        keys = part_keys(orders) if store.keeps else UNKEYED
    # Refined orders are checked in their flat form: paths, costs and properties
    # on the unrolled mission, the per-goal checks once per goal of the orders.
    flat = flatten(orders) if has_refinements(orders) else None
    checked = flat.orders if flat is not None else orders
    per_goal = flat.representative if flat is not None else orders
    built: list[MissionGraph] = [graph] if graph is not None and flat is None else []

    def mission_graph() -> MissionGraph:
        if not built:
            built.append(build_graph(orders) if flat is None else flat_graph(flat))
        return built[0]

    core = store.get("core", keys.core)
    if core is None:
        core = _core(orders, mission_graph(), flat)
        store.put("core", keys.core, core)
    meo = store.get("meo", keys.meo)
    if meo is None:
        meo = meo_only_findings(per_goal)
        store.put("meo", keys.meo, meo)
    limits = Limits.start(SOLVER_CALL_MS, solver_budget_s, solver_wall_cap_s, solver_clocks)
    logic, properties = _solver_parts(orders, checked, per_goal, mission_graph, cache, store,
                                      keys, limits)
    return _assembled(orders, reader_findings, core, meo, logic, properties, orders_digest)


def _solver_parts(orders: Orders, checked: Orders, per_goal: Orders,
                  mission_graph: Callable[[], MissionGraph], cache: LogicCache,
                  store: PartsCache, keys: PartKeys, limits: Limits
                  ) -> tuple[list[Finding], list[Finding]]:
    """The logic and path-property findings, from the parts cache or the solver; both share
    one budget, and a part with undecided goals is not kept."""
    logic = store.get("logic", keys.logic)
    if logic is None:
        logic = check_logic(per_goal, cache, limits=limits)
        if decided(logic):
            store.put("logic", keys.logic, logic)
    # No properties, no findings (check_properties would still parse the logic model).
    properties = store.get("properties", keys.properties) if orders.properties else []
    if properties is None:
        from .properties import check_properties  # orders with path properties only

        properties = check_properties(checked, mission_graph(), cache, limits=limits)
        if decided(properties):
            store.put("properties", keys.properties, properties)
    return logic, properties


def _assembled(orders: Orders, reader_findings: Sequence[Finding], core: CorePart,
               meo: list[Finding], logic: list[Finding], properties: list[Finding],
               orders_digest: str | None) -> Report:
    """The report from its parts, its findings in the order the report lists them."""
    findings = list(reader_findings)
    if has_refinements(orders):  # a procedure is named by a goal's refinement
        from .procedures import procedure_findings

        findings.extend(procedure_findings(orders))  # PROCEDURE: references not as pinned
    # Warnings an importer recorded in the orders (NPS default handlers) stay in every report;
    # the reader returns them too, so those already given are not repeated.
    given = {(f.code, f.subjects, f.message) for f in findings}
    findings.extend(f for f in core.defaulted if (f.code, f.subjects, f.message) not in given)
    findings.extend(core.structural)
    findings.extend(meo)
    findings.extend(core.descriptive)
    findings.extend(logic)
    findings.extend(properties)
    findings.extend(core.design)
    return Report(orders.id, orders_digest or digest(orders), findings, core.counts, core.costs,
                  orders, core.probabilities)


@dataclass(frozen=True)
class CorePart:
    """The findings and figures of the checks that read the mission's structure and costs."""

    defaulted: list[Finding]
    structural: list[Finding]  # structure, then budget
    descriptive: list[Finding]  # vehicle, text, geo
    design: list[Finding]  # rules' design, patterns
    counts: PathCounts | None
    costs: dict[str, WorstPath] | None
    probabilities: Probabilities | None


def _core(orders: Orders, graph: MissionGraph, flat: Flat | None = None) -> CorePart:
    if flat is None:
        structural = list(check_structure(orders, graph))
        checked = per_goal = orders
    else:
        # The top level as orders, each refinement as orders, and REFINE.
        structural = [*check_structure(orders), *refine_findings(orders), *flat.findings]
        checked, per_goal = flat.orders, flat.representative
    counts = count_paths(graph)
    legs = mission_legs(checked)
    costs = worst_paths(checked, graph, legs) if counts is not None else None
    structural.extend(check_budget(costs))
    descriptive = [*check_vehicle(per_goal), *check_text(per_goal),
                   *check_geo(checked, graph, legs)]
    if flat is not None:
        descriptive = dedupe_copies(descriptive)
    design = list(rules_findings(orders))
    if checked.properties:
        from .patterns import check_patterns

        design.extend(check_patterns(checked, graph, legs=legs))
    probabilities = None
    if counts is not None and declares_probabilities(checked):
        from .probability import outcome_probabilities

        probabilities = outcome_probabilities(checked, graph, legs)
    return CorePart(defaulted_findings(orders), structural, descriptive, design, counts, costs,
                    probabilities)


def decided(findings: Sequence[Finding]) -> bool:
    """No finding says the solver left something undecided (within the time budget, which
    another run may not exhaust): such a result is not kept for reuse."""
    return not any("undecided" in f.details for f in findings)
