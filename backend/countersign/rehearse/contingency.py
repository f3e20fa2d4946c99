"""The simulation's side of the contingency rules (seed 004): the simulated vehicle's
observations become observations of the default theory, its extension is computed and the
planned action is checked with eq. (17). The rules themselves live in `countersign.rules`.

An extension only changes when the observations change, and simulated observations change
rarely (a fix lost, a leak), so verdicts are cached by observation set: the rules cost almost
nothing per simulated second.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from ..orders.model import Goal, Orders
from ..rules import ActionVerdict, DefaultTheory, Extension, check_action, extension, theory_for

MAX_CACHE = 4_096


@dataclass(frozen=True)
class RuleVerdict:
    refused: bool
    outcome: str  # how a refused goal ends: violate when a safety rule decided, else fail
    reason: str
    safe_action: str | None
    because: tuple[str, ...]
    fired: tuple[str, ...]
    fired_new: tuple[str, ...]  # rules that fired now but not at the previous check


class Contingency:
    """A theory (or none) and a cache of verdicts."""

    def __init__(self, theory: DefaultTheory | None) -> None:
        self.theory = theory
        self._cache: dict[tuple[frozenset[tuple[str, bool]], str],
                          tuple[Extension, ActionVerdict]] = {}
        self._last_fired: frozenset[str] = frozenset()
        self._observables: frozenset[str] | None = None
        if theory is not None and theory.observables:
            self._observables = frozenset(lit.name for lit in theory.observables)

    @classmethod
    def for_orders(cls, orders: Orders) -> Contingency:
        return cls(theory_for(orders))

    @property
    def active(self) -> bool:
        return self.theory is not None

    def actions(self) -> tuple[str, ...]:
        return tuple(self.theory.actions) if self.theory is not None else ()

    def translate(self, observations: Mapping[str, bool]) -> dict[str, bool]:
        """Only what the theory declares observable (all when it declares nothing): an atom the
        theory never mentions cannot change its extension but would cost cache entries."""
        declared = self._observables
        if declared is None:
            return dict(observations)
        return {k: v for k, v in observations.items() if k.partition("(")[0] in declared}

    @staticmethod
    def planned_action(goal: Goal, actions: Sequence[str]) -> str:
        """The action name a theory uses for this goal: `params.action` when given, else the
        first of behaviour_area, goto_area, go_area that the theory names (seed 004 names
        transect_t1, goto_t1, go_home), else the behaviour."""
        action = goal.params.get("action")
        if isinstance(action, str) and action:
            return action
        behavior = (goal.behavior or "continue").strip().lower() or "continue"
        if goal.area:
            area = goal.area.lower()
            for candidate in (f"{behavior}_{area}", f"goto_{area}", f"go_{area}"):
                if candidate in actions:
                    return candidate
        return behavior

    def check(self, observations: Mapping[str, bool], action: str) -> RuleVerdict | None:
        theory = self.theory
        if theory is None:
            return None
        obs = self.translate(observations)
        key = (frozenset(obs.items()), action)
        cached = self._cache.get(key)
        if cached is None:
            ext = extension(theory, obs)
            verdict = check_action(theory, ext, action)
            if len(self._cache) >= MAX_CACHE:
                self._cache.clear()
            cached = self._cache[key] = (ext, verdict)
        ext, verdict = cached
        fired = tuple(ext.fired)
        fired_new = tuple(r for r in fired if r not in self._last_fired)
        self._last_fired = frozenset(fired)
        because = tuple(verdict.because)
        if verdict.allowed:
            return RuleVerdict(False, "succeed", verdict.explanation, None, because, fired,
                               fired_new)
        safety = any(self._kind(rule_id) == "safety" for rule_id in because)
        return RuleVerdict(True, "violate" if safety else "fail", verdict.explanation,
                           verdict.action_to_take, because, fired, fired_new)

    def _kind(self, rule_id: str) -> str | None:
        assert self.theory is not None
        try:
            return self.theory.rule(rule_id).kind
        except KeyError:
            return None
