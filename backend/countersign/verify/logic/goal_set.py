"""The goal-set API: can these goals and constraints hold together (explain)?"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ...orders.findings import Finding
from ...orders.model import Orders
from ..expressions import (
    Translator,
)
from .constants import DEFAULT_TIMEOUT_MS, ItemKind
from .items import Item, Part
from .limits import Limits
from .model import LogicModel, ParsedConstraint, _merge_reads
from .run import LogicRun, sorted_parts
from .wording import core_sentence, join_words


class UnknownIds(ValueError):
    """Goal or constraint ids that the orders do not define."""


@dataclass(frozen=True)
class GoalSetResult:
    goals: tuple[str, ...]
    constraints: tuple[str, ...]
    # True: they can all hold; False: they cannot; None: the solver could not decide.
    consistent: bool | None
    # The minimal incompatible subset: removing any one of these makes the rest consistent.
    core_goals: tuple[str, ...] = ()
    core_constraints: tuple[str, ...] = ()
    # Statements of the vehicle and quantity domains the incompatibility also rests on.
    background: tuple[str, ...] = ()
    explanation: str = ""
    reasons: tuple[Part, ...] = ()
    minimal: bool = True
    # For a consistent set: one state per goal in which everything holds.
    witness: dict[str, dict[str, str]] = field(default_factory=dict)
    not_applicable: tuple[str, ...] = ()
    findings: tuple[Finding, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {
            "goals": list(self.goals),
            "constraints": list(self.constraints),
            "consistent": self.consistent,
            "core": {"goals": list(self.core_goals), "constraints": list(self.core_constraints),
                     "background": list(self.background)},
            "minimal": self.minimal,
            "explanation": self.explanation,
            "reasons": [p.to_json() for p in self.reasons],
            "witness": self.witness,
            "not_applicable": list(self.not_applicable),
            "findings": [f.to_json() for f in self.findings],
        }


def explain_goal_set(
    orders: Orders,
    goal_ids: Sequence[str] | None = None,
    constraint_ids: Sequence[str] | None = None,
    *,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
    total_timeout_s: float = 30.0,
) -> GoalSetResult:
    """Can these goals run as ordered under these constraints? Each goal runs in its own state
    (its envelope and facts, the vehicle envelope, the quantity domains) and each constraint
    holds in the state of every selected goal in its scope. When they cannot, the answer names
    a minimal incompatible subset of the goals and constraints (seed 001, Algorithm 1) and
    explains it. `goal_ids` None means every goal; `constraint_ids` None means every constraint
    that applies to a selected goal."""
    model = LogicModel(orders)
    selection = _Selection.of(model, goal_ids, constraint_ids)
    run = LogicRun(model, None, Limits.start(timeout_ms, total_timeout_s))
    return _Explain(model, run, selection).answer()


@dataclass
class _Selection:
    """The goals and constraints asked about, and the selected ones left out (with why)."""

    goals: list[str]
    chosen: list[ParsedConstraint]
    not_applicable: tuple[str, ...]
    # Selected constraints whose expression is broken: left out and reported.
    bad: tuple[Finding, ...]

    @classmethod
    def of(cls, model: LogicModel, goal_ids: Sequence[str] | None,
           constraint_ids: Sequence[str] | None) -> _Selection:
        orders = model.orders
        goals = list(dict.fromkeys(goal_ids)) if goal_ids is not None else list(model.goals)
        unknown = [g for g in goals if g not in model.goals]
        all_constraints = {c.id for c in orders.constraints}
        if constraint_ids is not None:
            unknown += [c for c in dict.fromkeys(constraint_ids) if c not in all_constraints]
        if unknown:
            raise UnknownIds(f"not in these orders: {', '.join(unknown)}")
        selected = set(goals)
        applicable = [c for c in model.constraints
                      if c.mission or c.goals & selected]
        if constraint_ids is not None:
            wanted = set(constraint_ids)
            chosen = [c for c in model.constraints if c.id in wanted]
            not_applicable = tuple(c.id for c in chosen if c not in applicable)
            chosen = [c for c in chosen if c in applicable]
        else:
            chosen = applicable
            not_applicable = ()
            wanted = {c.id for c in orders.constraints
                      if c.applies_to == "mission" or set(c.applies_to) & selected}
        bad = tuple(f for f in model.expr_findings
                    if f.details.get("field") == "expr" and f.subjects[0] in wanted)
        return cls(goals, chosen, not_applicable, bad)


def _unit(key: str, kind: ItemKind, subject: str, phrase: str, parts: list[Item]) -> Item:
    """One item that states all of `parts` (a goal, or a constraint in every goal's state)."""
    def build(translator: Translator) -> str:
        formulas = [p.formula(translator) for p in parts]
        if not formulas:
            return "true"
        return formulas[0] if len(formulas) == 1 else f"(and {' '.join(formulas)})"

    return Item(key, kind, subject, phrase, key, build, shared=False,
                quantities=tuple(sorted({q for p in parts for q in p.quantities})))


class _Explain:
    """The fine items (a copy per goal, suffix @goal, of envelopes, facts, constraints and
    background), the coarse units over them, and the answer the session gives."""

    def __init__(self, model: LogicModel, run: LogicRun, selection: _Selection) -> None:
        self.model = model
        self.session = run.session
        self.selection = selection
        self.goals = selection.goals
        self.chosen_ids = tuple(dict.fromkeys(c.id for c in selection.chosen))
        self.fine_goal: dict[str, list[Item]] = {}
        self.fine_constraint: dict[str, list[Item]] = {c.key: [] for c in selection.chosen}
        self.background: list[Item] = []
        for gid in self.goals:
            goal = model.goals[gid]
            suffix = f"@{gid}"
            in_scope = [c for c in selection.chosen if c.mission or gid in c.goals]
            needs = _merge_reads(c.reads for c in in_scope)
            self.fine_goal[gid] = [model.envelope_item(goal, n, suffix)
                                   for n in sorted(goal.envelope)]
            self.fine_goal[gid] += model.fact_items(goal, needs, suffix)
            for c in in_scope:
                self.fine_constraint[c.key].append(model.constraint_item(c, suffix))
            self.background += model.background(set(goal.envelope) | needs.quantities, suffix)
        self.units = [_unit(f"goal:{gid}", "goal", gid, model.goal_label(model.goals[gid]),
                            self.fine_goal[gid]) for gid in self.goals]
        self.units += [_unit(f"set:{c.key}", "constraint", c.id,
                             f"{c.id} requires {model.words(c.expr)}",
                             self.fine_constraint[c.key]) for c in selection.chosen]

    def result(self, consistent: bool | None, explanation: str, **more: Any) -> GoalSetResult:
        return GoalSetResult(goals=tuple(self.goals), constraints=self.chosen_ids,
                             consistent=consistent, explanation=explanation,
                             not_applicable=self.selection.not_applicable,
                             findings=self.selection.bad, **more)

    def answer(self) -> GoalSetResult:
        session, units, background = self.session, self.units, self.background
        every = units + background + [i for items in self.fine_goal.values() for i in items] + [
            i for items in self.fine_constraint.values() for i in items]
        with session.scope(every):
            first = session.check(background)
            if first.status == "unsat":
                core, minimal = session.minimal_core(first.core)
                parts = tuple(sorted_parts(core))
                return self.result(False, core_sentence(parts) + " Nothing can run on this "
                                   "vehicle.", background=tuple(p.phrase for p in parts),
                                   reasons=parts, minimal=minimal)
            result = session.check(units + background)
            if result.status == "unknown":
                return self.result(None, f"The solver could not decide ({result.reason}).")
            if result.status == "sat":
                return self._consistent()
            in_core = [u for u in units if u in result.core]
            core_units, minimal = session.minimal_core(in_core, background)
            reasons = self._reasons(core_units)
        return self._incompatible(core_units, minimal, reasons)

    def _consistent(self) -> GoalSetResult:
        if not self.goals:
            return self.result(True, "No goal selected: nothing to check.")
        witness: dict[str, dict[str, str]] = {}
        for gid in self.goals:
            names = sorted({q for i in self.fine_goal[gid] for q in i.quantities} | {
                q for c in self.selection.chosen if c.mission or gid in c.goals
                for q in c.reads.quantities})
            if names:
                witness[gid] = self.session.witness(names, f"@{gid}")
        return self.result(True, f"{join_words(list(self.goals))} can run as ordered under "
                           f"{join_words(list(self.chosen_ids)) or 'no constraint'}.",
                           witness=witness)

    def _reasons(self, core_units: list[Item]) -> tuple[Part, ...]:
        """The fine statements behind the minimal units, shrunk to a minimal core."""
        fine: list[Item] = []
        for u in core_units:
            if u.kind == "goal":
                fine += self.fine_goal[u.subject]
            else:
                fine += self.fine_constraint[u.key[len("set:"):]]
        fine_result = self.session.check(fine + self.background)
        if fine_result.status != "unsat":
            return ()
        fine_core, _ = self.session.minimal_core(fine_result.core)
        return tuple(sorted_parts(fine_core))

    def _incompatible(self, core_units: list[Item], minimal: bool,
                      reasons: tuple[Part, ...]) -> GoalSetResult:
        core_goals = tuple(u.subject for u in core_units if u.kind == "goal")
        core_constraints = tuple(u.subject for u in core_units if u.kind == "constraint")
        explanation = core_sentence(reasons) if reasons else (
            f"{join_words(list(core_goals + core_constraints))} cannot hold together.")
        return self.result(
            False,
            explanation,
            core_goals=core_goals,
            core_constraints=core_constraints,
            background=tuple(p.phrase for p in reasons if p.kind in {"vehicle", "domain"}),
            reasons=reasons,
            minimal=minimal,
        )


def format_goal_set(result: GoalSetResult) -> str:
    """The answer as text, for `countersign explain`."""
    lines = []
    subject = ", ".join([*result.goals, *result.constraints]) or "nothing"
    if result.consistent is True:
        lines.append(f"Consistent: {subject}")
        lines.append(f"  {result.explanation}")
        for gid, values in result.witness.items():
            shown = ", ".join(f"{k} = {v}" for k, v in values.items())
            lines.append(f"  e.g. {gid}: {shown}")
    elif result.consistent is False:
        core = ", ".join([*result.core_goals, *result.core_constraints])
        lines.append(f"Incompatible: {subject}")
        if core:
            lines.append(f"  Minimal incompatible subset: {core}"
                         + ("" if result.minimal else " (may not be minimal: solver timeout)"))
        lines.append(f"  {result.explanation}")
    else:
        lines.append(f"Undecided: {subject}")
        lines.append(f"  {result.explanation}")
    if result.not_applicable:
        lines.append(f"  Not applicable to the selected goals: {', '.join(result.not_applicable)}")
    for finding in result.findings:
        lines.append(f"  {finding.code}: {finding.message}")
    return "\n".join(lines) + "\n"
