"""The logic check's findings (CONTRADICTION, NORM, VACUOUS, ...): `check_logic`."""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from ...orders.findings import Finding, error, warning
from ...orders.model import Goal, Orders
from ..expressions import (
    quantity_words,
    with_unit,
)
from .cache import LogicCache
from .collector import collector_paused
from .constants import DEFAULT_TIMEOUT_MS, DEFAULT_TOTAL_S, GOAL_KINDS
from .items import Item
from .limits import BUDGET_SPENT, OUT_OF_TIME, WALL_CAP_REACHED, Limits
from .model import LogicModel
from .results import Core, GoalOutcome, GoalResult, MissionResult, Risk
from .run import LogicRun
from .wording import _core_details, _ids, _subjects, core_sentence, join_words

# Vacuity of many constraints settled from shared models (False: one check per constraint, the
# reference the batched path is tested against).
BATCH_VACUITY = True


def check_logic(
    orders: Orders,
    cache: LogicCache | None = None,
    *,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
    total_timeout_s: float = DEFAULT_TOTAL_S,
    limits: Limits | None = None,
) -> list[Finding]:
    """EXPR, CONTRADICTION, NORM and VACUOUS findings of a set of orders.

    Pass a long-lived LogicCache to re-solve only the units whose inputs changed. Every solver
    call stops after `timeout_ms`, and the whole check after `total_timeout_s` of CPU time
    (or its wall-clock cap, limits.py); `limits`, when given, are those instead (a validation
    shares one with check_properties). What could not be decided is reported as a warning."""
    with collector_paused():
        return _check_logic(orders, cache, limits or Limits.start(timeout_ms, total_timeout_s))


def _check_logic(orders: Orders, cache: LogicCache | None, limits: Limits) -> list[Finding]:
    model = cache.model(orders) if cache is not None else LogicModel(orders)
    with model.lock:
        run = LogicRun(model, cache, limits)
        findings = list(model.expr_findings)
        mission = run.mission()
        findings.extend(_mission_findings(model, mission))
        findings.extend(_goal_findings(model, run, mission))
        if not mission.cores:
            findings.extend(_vacuous_findings(model, run, mission))
    return findings


def _mission_findings(model: LogicModel, mission: MissionResult) -> Iterator[Finding]:
    for core in mission.cores:
        constraints = _ids(core.parts, "constraint")
        verb = "applies" if len(constraints) == 1 else "apply"
        applies = f" while {join_words(constraints)} {verb}" if constraints else ""
        yield error(
            "CONTRADICTION",
            _subjects([], core.parts),
            f"{core_sentence(core.parts)} No goal can run as ordered on this vehicle{applies}.",
            **_core_details(core),
        )
    if mission.undecided:
        yield warning(
            "CONTRADICTION",
            [c.id for c in model.mission_constraints] or [model.orders.id],
            f"The solver could not decide whether the mission-wide constraints can hold on "
            f"this vehicle ({mission.undecided}).",
            undecided=mission.undecided,
        )


def _goal_findings(model: LogicModel, run: LogicRun, mission: MissionResult) -> Iterator[Finding]:
    shared: dict[tuple[str, ...], tuple[Core, list[str]]] = {}
    out_of_time: dict[str, list[str]] = {}
    if model.goals:  # the run's live block, as the goals' units hold it (vacuity's keys too)
        run.block(mission.quarantined)
    for goal in model.goals.values():
        outcome = _goal_outcome(model, run, goal, mission.quarantined)
        for core in outcome.shared:
            shared.setdefault(tuple(p.key for p in core.parts), (core, []))[1].append(goal.id)
        yield from outcome.findings
        if outcome.result.undecided in OUT_OF_TIME:
            out_of_time.setdefault(outcome.result.undecided, []).append(goal.id)
    for core, goals in shared.values():
        constraints = _ids(core.parts, "constraint")
        yield error(
            "CONTRADICTION",
            _subjects(constraints, core.parts) + [g for g in goals if g not in constraints],
            f"{core_sentence(core.parts)} {'Goal' if len(goals) == 1 else 'Goals'} "
            f"{join_words(goals)} cannot run as ordered.",
            goals=goals,
            **_core_details(core),
        )
    for reason, goals in out_of_time.items():
        yield _out_of_time(goals, reason, run.limits)


def _out_of_time(goals: list[str], reason: str, limits: Limits) -> Finding:
    """The goals the limits left undecided, in one warning that says which limit it was."""
    why = "" if reason == BUDGET_SPENT else f" ({_reason_words(reason, limits)})"
    return warning(
        "CONTRADICTION",
        goals,
        f"The logic checks ran out of time{why} before deciding {len(goals)} goal(s): "
        f"{', '.join(goals[:20])}{' ...' if len(goals) > 20 else ''}.",
        undecided=reason,
    )


def _goal_outcome(model: LogicModel, run: LogicRun, goal: Goal,
                  quarantined: frozenset[str]) -> GoalOutcome:
    """The goal's result and findings: carried from the model before an edit when the cache
    still holds that very result under its key (the key, and so the result and the words,
    are what solving the goal again would give), else from `run.goal_keyed`."""
    memo = (goal.id, quarantined)
    carried = model.goal_outcomes.get(memo)
    if carried is not None and run.cache.holds(carried.key, carried.result):
        return carried
    key, result = run.goal_keyed(goal, quarantined)
    shared = tuple(core for core in result.contradictions
                   if not any(p.kind in GOAL_KINDS for p in core.parts))
    outcome = model.goal_outcomes[memo] = GoalOutcome(
        key, result, tuple(_worded_goal_findings(model, goal, result)), shared)
    return outcome


def _worded_goal_findings(model: LogicModel, goal: Goal, result: GoalResult
                          ) -> Iterator[Finding]:
    """A goal's own findings (the contradictions with a statement of the goal's, refusals,
    risks, an undecided solver), in the order the report lists them."""
    for core in result.contradictions:
        if not any(p.kind in GOAL_KINDS for p in core.parts):
            continue
        constraints = _ids(core.parts, "constraint")
        if constraints:
            why = f" without violating {join_words(constraints)}"
        elif any(p.kind == "vehicle" for p in core.parts):
            why = " on this vehicle"
        else:
            why = ""
        yield error(
            "CONTRADICTION",
            _subjects([goal.id], core.parts),
            f"{core_sentence(core.parts)} {goal.id} cannot run as ordered{why}.",
            goal=goal.id,
            **_core_details(core),
        )
    for core in result.refusals:
        yield _refusal(model, goal, core)
    # In the orders' norm order: a unit's key does not hold the order of its norms, so a
    # result kept from before the norms were reordered lists its risks in the old order.
    if result.risks:
        position = {n.key: i for i, n in enumerate(model.norms)}
        for risk in sorted(result.risks, key=lambda r: position.get(r.norm.key, len(position))):
            yield _risk(model, goal, risk)
    if result.undecided and result.undecided not in OUT_OF_TIME:
        scope = [c.id for c in model.in_scope(goal.id)]
        yield warning(
            "CONTRADICTION",
            [goal.id],
            f"The solver could not decide whether {model.goal_label(goal)} can run as ordered "
            f"under its constraints and norms ({result.undecided}). Simplify the expressions "
            f"that apply to it{': ' + ', '.join(scope) if scope else ''}.",
            goal=goal.id,
            undecided=result.undecided,
        )


def _norm_context_subjects(model: LogicModel, goal: Goal, core: Core) -> list[str]:
    norms = [n for n in model.norms if n.norm.id in _ids(core.parts, "norm")]
    tags = [n.tag for n in norms if n.tag is not None]
    if not tags:
        facts = model.facts(goal)
        tags = [p.key.split(":", 2)[2] for p in core.parts
                if p.kind == "context" and p.key.split(":", 2)[2] in facts.tags]
    if not tags and goal.area:
        tags = [goal.area]
    return list(dict.fromkeys(tags))


def _refusal(model: LogicModel, goal: Goal, core: Core) -> Finding:
    norms = _ids(core.parts, "norm")
    texts = [n.norm.text for n in model.norms if n.norm.id in norms and n.norm.text]
    named = join_words(norms) + (f" ({'; '.join(texts)})" if texts else "")
    verb = "conflict" if len(norms) > 1 else "break"
    lead = (f"Refusal: {model.goal_label(goal)} cannot run as ordered without breaking {named}"
            if len(norms) == 1 else
            f"Refusal: {model.goal_label(goal)} cannot run as ordered: the norms {named} {verb}")
    return error(
        "NORM",
        [goal.id, *norms, *_norm_context_subjects(model, goal, core)],
        f"{lead}. {core_sentence(core.parts)}",
        goal=goal.id,
        norms=norms,
        **_core_details(core),
    )


def _risk(model: LogicModel, goal: Goal, risk: Risk) -> Finding:
    norm = next((n for n in model.norms if n.key == risk.norm.key), None)
    text = f" ({norm.norm.text})" if norm is not None and norm.norm.text else ""
    values = join_words([
        f"{quantity_words(q, model.quantities)} {with_unit(v, model.unit(q))}"
        if v not in {"true", "false"} else f"{quantity_words(q, model.quantities)} {v}"
        for q, v in risk.witness
    ])
    where = f" in {model.area_label(goal.area)}" if goal.area else ""
    subjects = [goal.id, risk.norm.subject]
    if norm is not None and norm.tag is not None:
        subjects.append(norm.tag)
    elif goal.area:
        subjects.append(goal.area)
    return warning(
        "NORM",
        subjects,
        f"{model.goal_label(goal)} may break {risk.norm.subject}{text}: {risk.norm.phrase}, "
        f"and nothing in the orders of {goal.id} rules out {values or 'a breach'}{where}. "
        "Narrow the goal's envelope or add a constraint.",
        goal=goal.id,
        norm=risk.norm.subject,
        witness=dict(risk.witness),
    )


def _vacuous_findings(
    model: LogicModel, run: LogicRun, mission: MissionResult
) -> Iterator[Finding]:
    if BATCH_VACUITY:
        run.vacuous_batch(c for c in model.constraints if c.key not in mission.quarantined)
    undecided: dict[str, list[str]] = {}
    for c in model.constraints:
        if c.key in mission.quarantined:
            continue
        result = run.vacuous(c)
        if result.undecided is not None:
            undecided.setdefault(result.undecided, []).append(c.id)
        if result.core is None:
            continue
        reasons = [p for p in result.core.parts if p.kind in {"vehicle", "domain"}]
        if reasons:
            why = (f"{join_words([p.phrase for p in reasons])}, so {model.words(c.expr)} "
                   "always holds")
        else:
            why = f"{model.words(c.expr)} holds whatever the vehicle does"
        yield warning(
            "VACUOUS",
            _subjects([c.id], reasons),
            f"{c.id} can never trigger: {why}. A constraint that cannot be violated is likely "
            "a typo.",
            **_core_details(result.core),
        )
    # Said, not dropped: a report without them would read as "none can never trigger".
    for reason, constraints in undecided.items():
        yield warning(
            "VACUOUS",
            constraints,
            f"The solver could not decide whether {len(constraints)} constraint(s) can ever "
            f"trigger ({_reason_words(reason, run.limits)}): {', '.join(constraints[:20])}"
            f"{' ...' if len(constraints) > 20 else ''}.",
            undecided=reason,
        )


def _reason_words(reason: str, limits: Limits) -> str:
    if reason == WALL_CAP_REACHED:
        return (f"the machine was too busy to finish within the wall-clock cap of "
                f"{limits.wall_cap_s:g} s")
    return reason


def core_satisfiable(
    orders: Orders, keys: Iterable[str], *, timeout_ms: int = DEFAULT_TIMEOUT_MS
) -> bool | None:
    """Whether the items named by keys (as reported in a finding's core) can hold together;
    None when undecided. For tests and tools that want to re-check a reported core."""
    model = LogicModel(orders)
    run = LogicRun(model, None, Limits.start(timeout_ms, timeout_ms / 1000 * 10))
    wanted = set(keys)
    pool: dict[str, Item] = {}
    everything = frozenset[str]()
    for goal in model.goals.values():
        norms = model.relevant_norms(goal)
        items, _ = run.goal_items(goal, everything, [model.norm_reads(n) for n in norms])
        for item in items:
            pool[item.key] = item
        for pair in (model.norm_items(n) for n in norms):
            for item in pair:
                pool[item.key] = item
    for c in model.constraints:
        pool.setdefault(c.key, model.constraint_item(c))
        negation = model.constraint_item(c, negate=True)
        pool[negation.key] = negation
        for item in model.background(c.reads.quantities):
            pool[item.key] = item
    for item in model.background(model.vehicle.envelope if model.vehicle else ()):
        pool[item.key] = item
    missing = wanted - set(pool)
    if missing:
        raise KeyError(f"unknown core items: {sorted(missing)}")
    items = [pool[k] for k in sorted(wanted)]
    session = run.session
    with session.scope(items):
        result = session.check(items)
    return None if result.status == "unknown" else result.status == "sat"
