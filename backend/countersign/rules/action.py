"""Checking a planned action against the rules (seed 004 section IV-C, steps 3 and 5).

The planned action a0 is added as the observation next_action(a0) together with the default
of eq. (17), `next_action(a0) : do_safe(a0) / do_safe(a0)`, ranked below every rule of the
theory. In the resulting extension
  * a do_safe(b) with b != a0 is a safety action: it overrides the plan (step 3);
  * otherwise do_safe(a0) means the plan may go ahead;
  * neither means an exception (e.g. eq. 18 `... -> not do_safe(a0)`) forbids the action and
    no rule says what to do instead: the verdict refuses it.
"""

from __future__ import annotations

from dataclasses import dataclass

from .engine import EQ17_ID, Extension, compute
from .syntax import Literal, parse_atom
from .theory import DO_SAFE, NEXT_ACTION, DefaultTheory


@dataclass(frozen=True)
class ActionVerdict:
    planned: str
    allowed: bool
    action_to_take: str | None
    because: tuple[str, ...]
    explanation: str
    extension: Extension | None = None

    def to_json(self) -> dict[str, object]:
        return {
            "planned": self.planned,
            "allowed": self.allowed,
            "action_to_take": self.action_to_take,
            "because": list(self.because),
            "explanation": self.explanation,
        }


def _why(ext: Extension, literal: str) -> tuple[str, ...]:
    """The rules that led to `literal`: its deriving rule and, recursively, theirs."""
    theory = ext.theory
    chain: list[str] = []
    todo = [literal]
    seen: set[str] = set()
    while todo and len(chain) < 50:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        rule_id = ext.derived_by.get(current)
        if rule_id is None or rule_id == "observed":
            continue
        chain.append(rule_id)
        if theory is None or rule_id == EQ17_ID:
            continue
        try:
            rule = theory.rule(rule_id)
        except KeyError:
            continue
        # Body literals of a grounded rule: find the ones that hold (variables bound).
        for body in rule.body:
            if body.has_variable:
                todo.extend(lit for lit in ext.literals if _matches(body, lit))
            else:
                todo.append(str(body))
    return tuple(dict.fromkeys(chain))


def _matches(pattern: Literal, text: str) -> bool:
    prefix = ("" if pattern.positive else "not ") + pattern.name + "("
    return text.startswith(prefix)


def check_action(
    theory_or_ext: DefaultTheory | Extension, extension: Extension, planned_action: str
) -> ActionVerdict:
    """Seed 004 eq. (17): may the vehicle do `planned_action`, and if not, what instead?"""
    action = parse_atom(planned_action)
    if action.arg is not None:
        raise ValueError(f"{planned_action!r}: an action is a name such as surface or go_home")
    theory = theory_or_ext if isinstance(theory_or_ext, DefaultTheory) else theory_or_ext.theory
    if theory is None:
        raise ValueError("the extension carries no theory; pass the theory itself")
    a0 = action.name
    observations = extension.observation_map()
    observations[str(Literal(NEXT_ACTION, a0))] = True
    after = compute(theory, observations, with_eq17=True)
    overriding = [a for a in after.safe_actions if a != a0]
    note = (
        f" Contradictory observations or conclusions about {', '.join(after.contradictions)}."
        if after.contradictions
        else ""
    )

    def said(because: tuple[str, ...]) -> str:
        """The deciding rule's own words, when its author gave some."""
        for rule_id in because[:1]:
            try:
                text = theory.rule(rule_id).text.strip().rstrip(".")
            except KeyError:
                continue
            if text:
                return f" ({rule_id}: {text})"
        return ""

    if overriding:
        chosen = overriding[0]
        because = _why(after, f"{DO_SAFE}({chosen})")
        return ActionVerdict(
            a0, False, chosen, because,
            f"Planned action {a0} is overridden: the rules {', '.join(because)} require "
            f"{chosen} now{said(because)}." + note,
            after,
        )
    if after.holds(f"{DO_SAFE}({a0})"):
        because = _why(after, f"{DO_SAFE}({a0})")
        return ActionVerdict(
            a0, True, a0, because,
            f"Planned action {a0} is allowed: no rule prevents it and no safety action is "
            "due." + note,
            after,
        )
    because = _why(after, f"not {DO_SAFE}({a0})")
    if not because and EQ17_ID in after.blocked:
        because = (EQ17_ID,)
    return ActionVerdict(
        a0, False, None, because,
        f"Planned action {a0} is refused by {', '.join(because) or 'the rules'}{said(because)} "
        "and no rule names a safe alternative." + note,
        after,
    )
