"""Design-pattern checks of seed 004 section IV-B, reported as RULES findings.

The seed splits a theory into observed facts (W_obs), estimation (D_est, W_est), goal
(D_goal, W_goal) and safety rules (D_safety, W_safety) and gives a pattern for each:
  * estimation rules conclude estimated propositions only, never an observed one;
  * safety defaults have the form A : do_safe(a) / do_safe(a) (eq. 10), safety formulas
    conclude do_safe(a) or not do_safe(a) (eq. 11), and a is an action of the functional layer
    (a skill; here a vehicle behaviour);
  * goal rules conclude goal(Y) or not goal(Y) (eqs. 13, 14); emergency actions belong to
    safety rules, not goal rules;
  * a default is worth writing because an exception can defeat it (d_loc and phi_loc, eqs. 8-9;
    the leak exception to the shutdown default, eq. 12): a default nothing can defeat is a fact;
  * prerequisites range over observed or estimated predicates: an atom that nothing observes
    or concludes never holds, so the rules reading it never apply.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from ..orders.findings import Finding, error, warning
from ..orders.profile import trusted_behaviors
from .syntax import Literal
from .theory import DO_SAFE, GOAL, NEXT_ACTION, DefaultTheory, Rule

if TYPE_CHECKING:
    from ..orders.model import Orders

CODE = "RULES"


def _matches(produced: Literal, wanted: Literal) -> bool:
    """Can a conclusion `produced` (maybe with a variable) make `wanted` true?"""
    if produced.name != wanted.name or produced.positive != wanted.positive:
        return False
    if produced.arg is None or wanted.arg is None:
        return produced.arg == wanted.arg
    return produced.has_variable or wanted.has_variable or produced.arg == wanted.arg


def _complement_producers(theory: DefaultTheory, literal: Literal) -> list[Rule]:
    negated = literal.negated()
    return [rule for rule in theory.rules if _matches(rule.head, negated)]


def _observed(theory: DefaultTheory, literal: Literal) -> bool:
    # An observation sets an atom true or false, so it produces both polarities.
    return any(_matches(obs, Literal(literal.name, literal.arg)) for obs in theory.observables)


def _known_actions(theory: DefaultTheory, orders: Orders | None) -> tuple[set[str], str]:
    """What do_safe may name, and where that list comes from. With orders whose vehicle has
    a profile, its trusted behaviours are the truth (the rules' own `actions` list cannot
    widen them)."""
    vehicle = orders.target_vehicle() if orders is not None else None
    if vehicle is not None and (vehicle.behaviors or vehicle.features):
        return set(trusted_behaviors(vehicle)), f"behaviours of vehicle {vehicle.id}"
    return set(theory.actions), "rules.actions"


def _safe_actions(rules: Iterable[Rule]) -> list[tuple[Rule, Literal]]:
    return [
        (rule, lit)
        for rule in rules
        for lit in (*rule.body, rule.head)
        if lit.name == DO_SAFE and lit.arg is not None and not lit.has_variable
    ]


def design_findings(theory: DefaultTheory, orders: Orders | None = None) -> list[Finding]:
    findings: list[Finding] = []
    findings.extend(_pattern_findings(theory))
    findings.extend(_action_findings(theory, orders))
    findings.extend(_reachability_findings(theory))
    findings.extend(_exception_findings(theory))
    findings.extend(_conflict_findings(theory))
    return findings


def _pattern_findings(theory: DefaultTheory) -> list[Finding]:
    found: list[Finding] = []
    for rule in theory.rules:
        head = rule.head
        if rule.kind == "estimation" and theory.observables and _observed(theory, head):
            found.append(warning(
                CODE, [rule.id],
                f"Estimation rule {rule.id} concludes {head}, which the vehicle observes: "
                "estimation rules should infer hidden states only, never overrule an "
                "observation (seed 004 IV-B-2).",
            ))
        if rule.kind in ("safety", "estimation") and any(lit.name == GOAL for lit in rule.body):
            found.append(warning(
                CODE, [rule.id],
                f"{rule.kind.capitalize()} rule {rule.id} reads a goal: its prerequisites "
                "should be observed or estimated states only, so that a change of goal can "
                "never switch a safety reaction or an estimate (seed 004 eqs. 10-11).",
            ))
        safety_shape = head.name == DO_SAFE and (head.positive or not rule.is_default)
        if rule.kind == "safety" and not safety_shape:
            pattern = (
                "A : do_safe(a) / do_safe(a)" if rule.is_default
                else "A -> do_safe(a) or A -> not do_safe(a)"
            )
            found.append(error(
                CODE, [rule.id],
                f"Safety {'default' if rule.is_default else 'rule'} {rule.id} concludes "
                f"{head}; a safety rule has the form {pattern} (seed 004 eqs. 10-11).",
            ))
        elif rule.kind == "goal" and head.name == DO_SAFE:
            found.append(error(
                CODE, [rule.id],
                f"Goal rule {rule.id} orders {head}: goal rules choose goals (goal(Y)); "
                "immediate actions belong to safety rules (seed 004 IV-B-3, IV-B-4).",
            ))
        elif rule.kind == "goal" and head.name != GOAL:
            found.append(warning(
                CODE, [rule.id],
                f"Goal rule {rule.id} concludes {head}; goal rules conclude goal(Y) or "
                "not goal(Y) (seed 004 eqs. 13-14).",
            ))
        elif rule.kind in ("estimation", "observation") and head.name == DO_SAFE:
            found.append(warning(
                CODE, [rule.id],
                f"Rule {rule.id} ({rule.kind}) orders {head}; mark rules that order "
                "immediate actions as safety rules so they are reviewed as such.",
            ))
    return found


def _action_findings(theory: DefaultTheory, orders: Orders | None) -> list[Finding]:
    found: list[Finding] = []
    known, where = _known_actions(theory, orders)
    uses = _safe_actions(theory.rules)
    if uses and not known:
        found.append(warning(
            CODE, sorted({rule.id for rule, _ in uses}),
            "The rules order do_safe actions but name no actions: list the vehicle "
            "behaviours under rules.actions so that each do_safe action can be checked.",
        ))
        return found
    unknown: dict[str, list[str]] = {}
    for rule, lit in uses:
        if lit.arg not in known and lit.arg is not None:
            unknown.setdefault(lit.arg, []).append(rule.id)
    for action, rule_ids in unknown.items():
        found.append(error(
            CODE, list(dict.fromkeys(rule_ids)),
            f"do_safe({action}) is not a behaviour the vehicle can carry out (not among the "
            f"{where}: {', '.join(sorted(known))}).",
        ))
    return found


def _reachability_findings(theory: DefaultTheory) -> list[Finding]:
    found: list[Finding] = []
    if not theory.observables:
        if theory.rules:
            found.append(warning(
                CODE, list(theory.sources) or ["rules"],
                "The rules declare no observables, so it cannot be checked which "
                "prerequisites the vehicle can ever observe; list them under rules.observables.",
            ))
        return found
    heads = [rule.head for rule in theory.rules]

    def produced(lit: Literal) -> bool:
        if lit.name == NEXT_ACTION or _observed(theory, lit):
            return True
        return any(_matches(head, lit) for head in heads)

    for rule in theory.rules:
        clash = sorted({lit.atom for lit in rule.body if lit.negated() in rule.body})
        if clash:
            found.append(warning(
                CODE, [rule.id],
                f"{rule.id} requires both {clash[0]} and not {clash[0]}, so it can never apply.",
            ))
            continue
        missing = [str(lit) for lit in rule.body if not produced(lit)]
        if missing:
            kind = "default" if rule.is_default else "rule"
            found.append(warning(
                CODE, [rule.id],
                f"The {kind} {rule.id} reads {', '.join(missing)}, which nothing observes or "
                "concludes, so it can never apply.",
            ))
    return found


def _exception_findings(theory: DefaultTheory) -> list[Finding]:
    found: list[Finding] = []
    for rule in theory.defaults:
        defeaters = [r for r in _complement_producers(theory, rule.head) if r.id != rule.id]
        unconditional = [r for r in defeaters if not r.body and not r.is_default]
        if unconditional:
            found.append(warning(
                CODE, [rule.id, *(r.id for r in unconditional)],
                f"Default {rule.id} is shadowed: {unconditional[0].id} always concludes "
                f"{unconditional[0].head}, so the default never applies.",
            ))
            continue
        if defeaters or rule.kind == "action":
            continue
        if rule.kind == "safety":
            found.append(warning(
                CODE, [rule.id],
                f"Safety default {rule.id} ({rule.head}) has no exception: no rule concludes "
                f"not {rule.head}, so no situation (e.g. a leak that calls for surfacing "
                "instead) can cancel it; write it as a strict rule or add the exception "
                "(seed 004 eq. 11).",
            ))
        elif rule.kind == "estimation":
            found.append(warning(
                CODE, [rule.id],
                f"Estimation default {rule.id} assumes {rule.head} but no observation can "
                f"defeat it (nothing concludes {rule.head.negated()}); it is then a fact, "
                "not an estimate (seed 004 eqs. 8-9).",
            ))
    for rule in theory.strict:
        for target in rule.exception_to:
            try:
                default = theory.rule(target)
            except KeyError:
                found.append(error(
                    CODE, [rule.id],
                    f"Rule {rule.id} is declared an exception to {target}, which does not exist.",
                ))
                continue
            # The leak pattern of eq. 12 pairs a cancelling rule (not do_safe(shutdown)) with
            # an alternative (do_safe(surface)): an alternative action counts as exception too.
            alternative = rule.head.name == DO_SAFE == default.head.name and rule.head.positive
            if not alternative and not _matches(rule.head, default.head.negated()):
                found.append(warning(
                    CODE, [rule.id, target],
                    f"Rule {rule.id} is declared an exception to {target} but concludes "
                    f"{rule.head}, which does not contradict {default.head}.",
                ))
    return found


def _conflict_findings(theory: DefaultTheory) -> list[Finding]:
    found: list[Finding] = []
    strict = [r for r in theory.rules if not r.is_default]
    by_body: dict[frozenset[Literal], list[Rule]] = {}
    for rule in strict:
        by_body.setdefault(frozenset(rule.body), []).append(rule)
    for rules in by_body.values():
        for i, first in enumerate(rules):
            for second in rules[i + 1:]:
                if first.head == second.head.negated():
                    when = " and ".join(map(str, first.body)) or "always"
                    found.append(error(
                        CODE, [first.id, second.id],
                        f"{first.id} and {second.id} contradict each other ({when}: "
                        f"{first.head} and {second.head}).",
                    ))
    defaults = list(theory.defaults)
    for i, first in enumerate(defaults):
        for second in defaults[i + 1:]:
            if (set(first.body) == set(second.body) and first.head == second.head.negated()
                    and first.priority == second.priority):
                found.append(warning(
                    CODE, [first.id, second.id],
                    f"Defaults {first.id} and {second.id} have the same prerequisites and "
                    "opposite conclusions: only their order in the file decides which wins; "
                    "give one a priority or a more specific prerequisite.",
                ))
    # Goal defaults against safety: a goal that a safety rule may have to cancel is fine, but a
    # goal concluded strictly while a safety rule concludes its negation is a contradiction.
    for rule in theory.rules:
        if rule.kind == "goal" and rule.head.name == GOAL and rule.head.positive:
            for other in _complement_producers(theory, rule.head):
                if other.kind == "safety":
                    found.append(warning(
                        CODE, [rule.id, other.id],
                        f"Goal rule {rule.id} and safety rule {other.id} conclude opposite "
                        f"things about {rule.head}; keep goal changes in goal rules "
                        "and make the safety rule order a do_safe action.",
                    ))
    return found
