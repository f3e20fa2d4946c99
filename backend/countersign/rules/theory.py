"""A normal default theory (seed 004 section IV-B) and its reader.

Data format (the `rules` field of orders or of a vehicle profile):

    {"observables": ["gps_was_captured", "safety_sensor_failure(X)"],   # W_obs vocabulary
     "actions": ["surface", "shutdown"],                                # do_safe(a) behaviours
     "facts":    [{"id": "F1", "fact": "at(home)"}],                    # static W_obs
     "strict":   [{"id": "X1", "kind": "estimation", "if": [...], "then": "not localised",
                   "exception_to": ["D1"]}],                            # W_est, W_goal, W_safety
     "defaults": [{"id": "D1", "kind": "estimation", "if": [], "then": "localised",
                   "priority": 0}]}                                     # normal defaults

Every entry may carry `text` (plain words for the supervisor). Unknown keys are refused: a
misspelt "default" silently ignored would drop a safety rule.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final

from .syntax import Literal, LiteralSyntaxError, is_variable, parse_atom, parse_literal

if TYPE_CHECKING:
    from ..orders.model import Orders

KINDS: Final[tuple[str, ...]] = ("observation", "estimation", "goal", "safety", "action")
DO_SAFE: Final = "do_safe"
NEXT_ACTION: Final = "next_action"
GOAL: Final = "goal"
MAX_RULES: Final = 50_000
MAX_BODY: Final = 100
MAX_VARIABLES: Final = 2  # grounding costs |constants|^variables per rule
_ID = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.:\-]{0,99}")
_TOP_KEYS: Final = frozenset({"observables", "actions", "facts", "strict", "defaults"})
_FACT_KEYS: Final = frozenset({"id", "fact", "text"})
_STRICT_KEYS: Final = frozenset({"id", "kind", "if", "then", "exception_to", "text"})
_DEFAULT_KEYS: Final = frozenset({"id", "kind", "if", "then", "priority", "text"})


class TheoryError(ValueError):
    """Rules that cannot be read; `path` names the JSON location (e.g. rules.defaults[2].if[0])."""

    def __init__(self, path: str, message: str) -> None:
        super().__init__(f"{path}: {message}")
        self.path = path
        self.reason = message


@dataclass(frozen=True)
class Rule:
    """A fact (no body), a strict rule `body -> head`, or a normal default `body : head / head`."""

    id: str
    kind: str
    is_default: bool
    body: tuple[Literal, ...]
    head: Literal
    text: str = ""
    priority: int = 0
    exception_to: tuple[str, ...] = ()
    # Where the rule was read (for messages); not part of what the rule means.
    path: str = field(default="", compare=False)

    @property
    def is_fact(self) -> bool:
        return not self.is_default and not self.body

    @property
    def variables(self) -> tuple[str, ...]:
        seen: dict[str, None] = {}
        for literal in (*self.body, self.head):
            if literal.arg is not None and is_variable(literal.arg):
                seen.setdefault(literal.arg)
        return tuple(seen)

    def formula(self) -> str:
        body = " and ".join(map(str, self.body)) or "true"
        if self.is_default:
            return f"{body} : {self.head} / {self.head}"
        return str(self.head) if not self.body else f"{body} -> {self.head}"


@dataclass(frozen=True)
class DefaultTheory:
    facts: tuple[Rule, ...] = ()
    strict: tuple[Rule, ...] = ()
    defaults: tuple[Rule, ...] = ()
    observables: tuple[Literal, ...] = ()
    actions: tuple[str, ...] = ()
    # Where the theory came from, for messages ("rules", "vehicles[0].rules").
    sources: tuple[str, ...] = field(default=(), compare=False)
    # Grounded, compiled forms keyed by constant set (engine.py); not part of the value.
    _cache: dict[Any, Any] = field(default_factory=dict, init=False, compare=False, repr=False)

    @property
    def rules(self) -> tuple[Rule, ...]:
        return (*self.facts, *self.strict, *self.defaults)

    def __len__(self) -> int:
        return len(self.facts) + len(self.strict) + len(self.defaults)

    def rule(self, rule_id: str) -> Rule:
        for rule in self.rules:
            if rule.id == rule_id:
                return rule
        raise KeyError(rule_id)

    def merged(self, other: DefaultTheory) -> DefaultTheory:
        mine = {rule.id for rule in self.rules}
        for rule in other.rules:
            if rule.id in mine:
                raise TheoryError(rule.path, f"rule id {rule.id!r} is already used")
        return DefaultTheory(
            (*self.facts, *other.facts),
            (*self.strict, *other.strict),
            (*self.defaults, *other.defaults),
            tuple(dict.fromkeys((*self.observables, *other.observables))),
            tuple(dict.fromkeys((*self.actions, *other.actions))),
            (*self.sources, *other.sources),
        )


# ---------------------------------------------------------------------------------- reading


def _mapping(value: Any, path: str, keys: frozenset[str]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise TheoryError(path, f"expected an object, got {type(value).__name__}")
    unknown = sorted(str(k) for k in value if k not in keys)
    if unknown:
        raise TheoryError(
            f"{path}.{unknown[0]}", f"unknown key; expected one of {', '.join(sorted(keys))}"
        )
    return value


def _list(value: Any, path: str, limit: int) -> list[Any]:
    if value is None:
        return []
    if not isinstance(value, list):
        raise TheoryError(path, f"expected a list, got {type(value).__name__}")
    if len(value) > limit:
        raise TheoryError(path, f"at most {limit} entries")
    return value


def _text(value: Any, path: str) -> str:
    if value is None:
        return ""
    if not isinstance(value, str):
        raise TheoryError(path, "expected text")
    if len(value) > 10_000:
        raise TheoryError(path, "text may have at most 10000 characters")
    return value


def _id(value: Any, path: str) -> str:
    if not isinstance(value, str) or not _ID.fullmatch(value):
        raise TheoryError(
            path, "expected an id of letters, digits and _ . : - (at most 100 characters)"
        )
    return value


def _literal(value: Any, path: str) -> Literal:
    try:
        return parse_literal(value)
    except LiteralSyntaxError as exc:
        raise TheoryError(path, str(exc)) from None


def _kind(value: Any, path: str, fallback: str) -> str:
    if value is None:
        return fallback
    if value not in KINDS:
        raise TheoryError(path, f"unknown kind {value!r}; expected one of {', '.join(KINDS)}")
    return str(value)


def _rule(entry: Any, path: str, is_default: bool) -> Rule:
    data = _mapping(entry, path, _DEFAULT_KEYS if is_default else _STRICT_KEYS)
    if "id" not in data:
        raise TheoryError(f"{path}.id", "missing")
    if "then" not in data:
        raise TheoryError(f"{path}.then", "missing: a rule concludes one literal")
    body = tuple(
        _literal(item, f"{path}.if[{i}]")
        for i, item in enumerate(_list(data.get("if"), f"{path}.if", MAX_BODY))
    )
    priority = data.get("priority", 0)
    if isinstance(priority, bool) or not isinstance(priority, int) or abs(priority) > 10**6:
        raise TheoryError(f"{path}.priority", "expected an integer between -1000000 and 1000000")
    exception_to = tuple(
        _id(item, f"{path}.exception_to[{i}]")
        for i, item in enumerate(_list(data.get("exception_to"), f"{path}.exception_to", 100))
    )
    rule = Rule(
        id=_id(data["id"], f"{path}.id"),
        kind=_kind(data.get("kind"), f"{path}.kind", "estimation"),
        is_default=is_default,
        body=body,
        head=_literal(data["then"], f"{path}.then"),
        text=_text(data.get("text"), f"{path}.text"),
        priority=priority,
        exception_to=exception_to,
        path=path,
    )
    if len(rule.variables) > MAX_VARIABLES:
        raise TheoryError(path, f"a rule may use at most {MAX_VARIABLES} variables")
    return rule


def parse_theory(data: Mapping[str, Any], path: str = "rules") -> DefaultTheory:
    """Read a `rules` object; raises TheoryError naming the JSON path of the first problem."""
    top = _mapping(data, path, _TOP_KEYS)
    observables = []
    for i, item in enumerate(_list(top.get("observables"), f"{path}.observables", 10_000)):
        try:
            observables.append(parse_atom(item))
        except LiteralSyntaxError as exc:
            raise TheoryError(f"{path}.observables[{i}]", str(exc)) from None
    actions = tuple(
        _id(item, f"{path}.actions[{i}]")
        for i, item in enumerate(_list(top.get("actions"), f"{path}.actions", 10_000))
    )
    facts = []
    for i, entry in enumerate(_list(top.get("facts"), f"{path}.facts", MAX_RULES)):
        where = f"{path}.facts[{i}]"
        fact = _mapping(entry, where, _FACT_KEYS)
        if "fact" not in fact:
            raise TheoryError(f"{where}.fact", "missing")
        head = _literal(fact["fact"], f"{where}.fact")
        if head.has_variable:
            raise TheoryError(f"{where}.fact", "a fact names no variable")
        facts.append(
            Rule(
                _id(fact.get("id"), f"{where}.id"), "observation", False, (), head,
                _text(fact.get("text"), f"{where}.text"), path=where,
            )
        )
    strict = [
        _rule(entry, f"{path}.strict[{i}]", False)
        for i, entry in enumerate(_list(top.get("strict"), f"{path}.strict", MAX_RULES))
    ]
    defaults = [
        _rule(entry, f"{path}.defaults[{i}]", True)
        for i, entry in enumerate(_list(top.get("defaults"), f"{path}.defaults", MAX_RULES))
    ]
    seen: dict[str, str] = {}
    for rule in (*facts, *strict, *defaults):
        if rule.id in seen:
            raise TheoryError(f"{rule.path}.id", f"rule id {rule.id!r} is already used")
        seen[rule.id] = rule.path
    return DefaultTheory(
        tuple(facts), tuple(strict), tuple(defaults), tuple(dict.fromkeys(observables)),
        tuple(dict.fromkeys(actions)), (path,),
    )


def theory_for(orders: Orders) -> DefaultTheory | None:
    """The orders' rules merged after the target vehicle profile's; None when neither has any."""
    parts: list[DefaultTheory] = []
    vehicle = orders.target_vehicle()
    if vehicle is not None and vehicle.rules is not None:
        index = next(i for i, v in enumerate(orders.vehicles) if v is vehicle)
        parts.append(parse_theory(_dump(vehicle.rules), f"vehicles[{index}].rules"))
    if orders.rules is not None:
        parts.append(parse_theory(_dump(orders.rules), "rules"))
    if not parts:
        return None
    theory = parts[0]
    for part in parts[1:]:
        theory = theory.merged(part)
    return theory


def _dump(model: Any) -> dict[str, Any]:
    data: dict[str, Any] = model.model_dump(mode="json", exclude_unset=True, by_alias=True)
    return data
