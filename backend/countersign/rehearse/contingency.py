"""The simulation's side of the contingency rules (seed 004): turn what the simulated vehicle
observes into observations of the default theory, compute the extension, and check the
planned action with eq. (17). The rules themselves live in `rehearse.rules`.

An extension only changes when the observations change, and simulated observations change
rarely (a fix lost, a leak), so verdicts are cached by observation set: the rules cost almost
nothing per simulated second.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..orders.model import Goal, Orders

MAX_CACHE = 4_096
# A safety-sensor failure is observed per sensor (seed 004 eq. 12-14); the simulation has one
# failing sensor: the leak detector.
SENSOR_FAULTS = {"leak": "water_ingress"}


@dataclass(frozen=True)
class RuleVerdict:
    refused: bool
    outcome: str  # how a refused goal ends: violate for a safety action, else fail
    reason: str
    safe_action: str | None
    fired: tuple[str, ...]
    fired_new: tuple[str, ...]  # rules that fired now but not at the previous check


def _rules_module() -> Any | None:
    try:
        return importlib.import_module("countersign.rehearse.rules")
    except ImportError:  # the rules package is optional for the simulation
        return None


class Contingency:
    """A theory (or none) and a cache of verdicts."""

    def __init__(self, theory: Any | None, module: Any | None) -> None:
        self.theory = theory
        self._rules = module
        self._cache: dict[tuple[frozenset[tuple[str, bool]], str], tuple[Any, Any]] = {}
        self._last_fired: frozenset[str] = frozenset()
        self._observables = self._declared_observables()

    @classmethod
    def for_orders(cls, orders: Orders) -> Contingency:
        module = _rules_module()
        if module is None:
            return cls(None, None)
        return cls(module.theory_for(orders), module)

    @classmethod
    def none(cls) -> Contingency:
        return cls(None, None)

    @property
    def active(self) -> bool:
        return self.theory is not None and self._rules is not None

    def _declared_observables(self) -> frozenset[str] | None:
        if self.theory is None:
            return None
        names = {getattr(lit, "name", str(lit)) for lit in getattr(self.theory, "observables", ())}
        return frozenset(names) if names else None

    def translate(self, observations: Mapping[str, bool]) -> dict[str, bool]:
        """Simulation observations in the theory's vocabulary (only what it declares, when it
        declares its observables)."""
        out: dict[str, bool] = {}
        for name, value in observations.items():
            out[name] = value
        for fault, sensor in SENSOR_FAULTS.items():
            if observations.get(fault):
                out[f"safety_sensor_failure({sensor})"] = True
                out[f"safety_sensor_failure({fault})"] = True
        out.pop("safety_sensor_failure", None)
        declared = self._observables
        if declared is not None:
            out = {k: v for k, v in out.items() if k.partition("(")[0] in declared}
        return out

    def planned_action(self, goal: Goal) -> str:
        action = goal.params.get("action")
        if isinstance(action, str) and action:
            return action
        return (goal.behavior or "continue").strip() or "continue"

    def check(self, observations: Mapping[str, bool], goal: Goal) -> RuleVerdict | None:
        if not self.active:
            return None
        rules = self._rules
        assert rules is not None
        obs = self.translate(observations)
        action = self.planned_action(goal)
        key = (frozenset(obs.items()), action)
        cached = self._cache.get(key)
        if cached is None:
            ext = rules.extension(self.theory, obs)
            verdict = rules.check_action(self.theory, ext, action)
            if len(self._cache) >= MAX_CACHE:
                self._cache.clear()
            cached = self._cache[key] = (ext, verdict)
        ext, verdict = cached
        fired = tuple(getattr(ext, "fired", ()))
        fired_set = frozenset(fired)
        fired_new = tuple(r for r in fired if r not in self._last_fired)
        self._last_fired = fired_set
        if verdict.allowed:
            return RuleVerdict(False, "succeed", verdict.explanation, None, fired, fired_new)
        because = tuple(verdict.because)
        safety = any(self._kind(rule_id) == "safety" for rule_id in because)
        outcome = "violate" if safety else "fail"
        return RuleVerdict(True, outcome, verdict.explanation, verdict.action_to_take, fired,
                           fired_new)

    def _kind(self, rule_id: str) -> str | None:
        try:
            return str(self.theory.rule(rule_id).kind)  # type: ignore[union-attr]
        except (KeyError, AttributeError):
            return None
