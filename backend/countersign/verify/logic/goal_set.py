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
from .model import LogicModel, _merge_reads
from .run import LogicRun, sorted_parts
from .session import Limits
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
    # Selected constraints whose expression is broken are left out and reported.
    bad = tuple(f for f in model.expr_findings
                if f.details.get("field") == "expr" and f.subjects[0] in wanted)
    chosen_ids = tuple(dict.fromkeys(c.id for c in chosen))
    run = LogicRun(model, None, Limits.start(timeout_ms, total_timeout_s))

    # Fine items: per goal copy (suffix @goal) of envelopes, facts, constraints and background.
    fine_goal: dict[str, list[Item]] = {}
    fine_constraint: dict[str, list[Item]] = {c.key: [] for c in chosen}
    background: list[Item] = []
    for gid in goals:
        goal = model.goals[gid]
        suffix = f"@{gid}"
        in_scope = [c for c in chosen if c.mission or gid in c.goals]
        needs = _merge_reads(c.reads for c in in_scope)
        fine_goal[gid] = [model.envelope_item(goal, n, suffix) for n in sorted(goal.envelope)]
        fine_goal[gid] += model.fact_items(goal, needs, suffix)
        for c in in_scope:
            fine_constraint[c.key].append(model.constraint_item(c, suffix))
        background += model.background(set(goal.envelope) | needs.quantities, suffix)

    def unit(key: str, kind: ItemKind, subject: str, phrase: str, parts: list[Item]) -> Item:
        def build(translator: Translator) -> str:
            formulas = [p.formula(translator) for p in parts]
            if not formulas:
                return "true"
            return formulas[0] if len(formulas) == 1 else f"(and {' '.join(formulas)})"

        return Item(key, kind, subject, phrase, key, build, shared=False,
                    quantities=tuple(sorted({q for p in parts for q in p.quantities})))

    units = [unit(f"goal:{gid}", "goal", gid, model.goal_label(model.goals[gid]),
                  fine_goal[gid]) for gid in goals]
    units += [unit(f"set:{c.key}", "constraint", c.id, f"{c.id} requires {model.words(c.expr)}",
                   fine_constraint[c.key]) for c in chosen]

    def answer(consistent: bool | None, explanation: str, **more: Any) -> GoalSetResult:
        return GoalSetResult(goals=tuple(goals), constraints=chosen_ids, consistent=consistent,
                             explanation=explanation, not_applicable=not_applicable,
                             findings=bad, **more)

    session = run.session
    every = units + background + [i for items in fine_goal.values() for i in items] + [
        i for items in fine_constraint.values() for i in items]
    with session.scope(every):
        first = session.check(background)
        if first.status == "unsat":
            core, minimal = session.minimal_core(first.core)
            parts = tuple(sorted_parts(core))
            return answer(False, core_sentence(parts) + " Nothing can run on this vehicle.",
                          background=tuple(p.phrase for p in parts), reasons=parts,
                          minimal=minimal)
        result = session.check(units + background)
        if result.status == "unknown":
            return answer(None, f"The solver could not decide ({result.reason}).")
        if result.status == "sat" and not goals:
            return answer(True, "No goal selected: nothing to check.")
        if result.status == "sat":
            witness: dict[str, dict[str, str]] = {}
            for gid in goals:
                names = sorted({q for i in fine_goal[gid] for q in i.quantities} | {
                    q for c in chosen if c.mission or gid in c.goals for q in c.reads.quantities})
                if names:
                    witness[gid] = session.witness(names, f"@{gid}")
            return answer(True, f"{join_words(list(goals))} can run as ordered under "
                          f"{join_words(list(chosen_ids)) or 'no constraint'}.", witness=witness)
        in_core = [u for u in units if u in result.core]
        core_units, minimal = session.minimal_core(in_core, background)
        # Explain with the fine statements behind the minimal units.
        fine: list[Item] = []
        for u in core_units:
            if u.kind == "goal":
                fine += fine_goal[u.subject]
            else:
                fine += fine_constraint[u.key[len("set:"):]]
        fine_result = session.check(fine + background)
        reasons: tuple[Part, ...] = ()
        if fine_result.status == "unsat":
            fine_core, _ = session.minimal_core(fine_result.core)
            reasons = tuple(sorted_parts(fine_core))
    core_goals = tuple(u.subject for u in core_units if u.kind == "goal")
    core_constraints = tuple(u.subject for u in core_units if u.kind == "constraint")
    explanation = core_sentence(reasons) if reasons else (
        f"{join_words(list(core_goals + core_constraints))} cannot hold together.")
    return answer(
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
