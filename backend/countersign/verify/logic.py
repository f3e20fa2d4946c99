"""Constraint logic with z3: contradictions, norms, vacuous constraints and goal-set consistency.

Seed 000 asks that orders be free of logical or legal contradictions; seed 002 turns
context-sensitive norms into solver constraints and explains a refusal with the unsatisfiable
core; seed 001 finds minimal unsatisfiable cores of goal sets (its Algorithm 1, used here).

Every statement the solver sees is an *item*: one bound of a goal's envelope, one bound of the
vehicle's envelope, one quantity domain, one constraint, one fact of a goal (its behaviour, its
area, whether its area carries a tag) or one norm. Each item is asserted behind its own
indicator literal, so a check is `solver.check(indicators...)`, the unsat core names items,
and Algorithm 1 shrinks z3's core to a minimal one that reads as a sentence:

    G5 Return to Base is ordered at depth 0-5 m, but C7 requires depth >= 20 m.

Checks come in units whose result depends only on their items: the mission (vehicle, domains,
mission-wide constraints), each goal (CONTRADICTION and NORM) and each constraint (VACUOUS).
A unit's cache key is the digest of its items' sources, so editing one goal re-checks only that
goal. Every solver call has a timeout and the whole run a time budget; an undecided check is a
warning finding, never a hang. z3 is imported and a context created only when some unit misses
the cache.
"""

from __future__ import annotations

import hashlib
import math
import re
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Literal

from ..orders.findings import Finding, error, warning
from ..orders.model import Goal, Norm, Orders, Quantity, Vehicle
from .expressions import (
    RESERVED,
    Compare,
    Context,
    Expr,
    ExprError,
    Facts,
    Logic,
    Not,
    Reads,
    Special,
    Text,
    Translator,
    TypeChecker,
    describe,
    fold,
    in_tag,
    number_words,
    parse,
    quantity_table,
    quantity_words,
    reads,
    smt_int,
    smt_real,
    tag_state,
    with_unit,
)
from .z3_adapter import check_assumptions

VERSION = "countersign.logic/1"
DEFAULT_TIMEOUT_MS = 2_000
DEFAULT_TOTAL_S = 60.0
MAX_CORES_PER_UNIT = 3
# Vacuity of many constraints settled from shared models (False: one check per constraint, the
# reference the batched path is tested against).
BATCH_VACUITY = True
# Longer expressions are cut short in explanations (the finding's details keep the ids).
MAX_WORDS = 240

ItemKind = Literal[
    "envelope", "behavior", "area", "context", "constraint", "vehicle", "domain", "norm",
    "breach", "negation", "goal", "property",
]
GOAL_KINDS = frozenset({"envelope", "behavior", "area", "context", "goal"})
_KIND_ORDER = {
    "goal": 0, "envelope": 0, "behavior": 1, "area": 1, "context": 2, "constraint": 3,
    "negation": 3, "property": 3, "norm": 4, "breach": 4, "vehicle": 5, "domain": 6,
}
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def _z3() -> Any:
    import z3

    return z3


# ---------------------------------------------------------------------------------------------
# Items


@dataclass(frozen=True)
class Part:
    """What a core reports about one item: enough to explain it, nothing to solve it."""

    key: str
    kind: str
    subject: str
    phrase: str

    def to_json(self) -> dict[str, str]:
        return {"key": self.key, "kind": self.kind, "subject": self.subject, "text": self.phrase}


class Item:
    """One statement for the solver, asserted behind its own indicator literal. Its phrase is
    built only when a core reports it."""

    __slots__ = ("_digest", "_phrase", "formula", "key", "kind", "quantities", "shared",
                 "source", "subject")

    def __init__(
        self,
        key: str,
        kind: ItemKind,
        subject: str,
        phrase: str | Callable[[], str],
        source: str,
        formula: Callable[[Translator], str],
        shared: bool = True,
        quantities: tuple[str, ...] = (),
    ) -> None:
        self.key = key
        self.kind = kind
        self.subject = subject
        self._phrase = phrase
        # Everything that determines the formula and the phrase: what a cache key digests.
        self.source = source
        self.formula = formula
        # Asserted once per session (same formula for every goal) rather than per goal scope.
        self.shared = shared
        self.quantities = quantities
        self._digest: bytes | None = None

    @property
    def digest(self) -> bytes:
        if self._digest is None:
            self._digest = hashlib.sha256(self.source.encode()).digest()
        return self._digest

    @property
    def phrase(self) -> str:
        if not isinstance(self._phrase, str):
            self._phrase = self._phrase()
        return self._phrase

    @property
    def part(self) -> Part:
        return Part(self.key, self.kind, self.subject, self.phrase)

    def __repr__(self) -> str:
        return f"Item({self.key!r})"


def _bound(value: float) -> Fraction | None:
    if not math.isfinite(value):
        return None
    return Fraction(repr(float(value)))


def _range_words(low: float, high: float, unit: str) -> str:
    lo, hi = number_words(low), number_words(high)
    if low == high:
        return with_unit(lo, unit)
    joiner = " to " if low < 0 or high < 0 else "-"
    return with_unit(f"{lo}{joiner}{hi}", unit)


def _interval_formula(
    quantity: str, spec: Quantity, low: float | None, high: float | None
) -> Callable[[Translator], str]:
    def build(translator: Translator) -> str:
        symbol, kind = translator.quantity(quantity)
        parts: list[str] = []
        lo = _bound(low) if low is not None else None
        hi = _bound(high) if high is not None else None
        if kind == "boolean":
            if lo is not None and lo > 0:
                parts.append(symbol)
            if hi is not None and hi < 1:
                parts.append(f"(not {symbol})")
        elif kind == "integer":
            if lo is not None:
                parts.append(f"(<= {smt_int(math.ceil(lo))} {symbol})")
            if hi is not None:
                parts.append(f"(<= {symbol} {smt_int(math.floor(hi))})")
        else:
            if lo is not None:
                parts.append(f"(<= {smt_real(lo)} {symbol})")
            if hi is not None:
                parts.append(f"(<= {symbol} {smt_real(hi)})")
        if not parts:
            return "true"
        return parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})"

    return build


def expr_formula(expr: Expr, negate: bool = False) -> Callable[[Translator], str]:
    def build(translator: Translator) -> str:
        term = translator.condition(expr)
        return f"(not {term})" if negate else term

    return build


def _with_suffix(build: Callable[[Translator], str], suffix: str) -> Callable[[Translator], str]:
    if not suffix:
        return build

    def suffixed(translator: Translator) -> str:
        return build(translator.with_suffix(suffix))

    return suffixed


# ---------------------------------------------------------------------------------------------
# The orders, parsed once: quantities, expressions, scopes and EXPR findings.


@dataclass(frozen=True)
class ParsedConstraint:
    id: str
    key: str
    text: str
    source: str
    expr: Expr
    reads: Reads
    mission: bool
    goals: frozenset[str]


@dataclass(frozen=True)
class ParsedNorm:
    norm: Norm
    key: str
    modality: Literal["forbidden", "obligated", "permitted"]
    context: Expr
    tag: str | None
    body: Expr
    reads: Reads


def _merge_reads(items: Iterable[Reads]) -> Reads:
    quantities: set[str] = set()
    tags: set[str] = set()
    behavior = area = False
    for r in items:
        quantities |= r.quantities
        tags |= r.tags
        behavior = behavior or r.behavior
        area = area or r.area
    return Reads(frozenset(quantities), frozenset(tags), behavior, area)


class LogicModel:
    """Everything the checks need from the orders, computed once per call."""

    def __init__(self, orders: Orders) -> None:
        self.orders = orders
        self.quantities = quantity_table(orders)
        self.checker = TypeChecker(self.quantities)
        self.vehicle: Vehicle | None = orders.target_vehicle()
        self.goals: dict[str, Goal] = orders.goal_index()
        self.areas = orders.area_index()
        self.expr_findings: list[Finding] = []
        self.constraints: list[ParsedConstraint] = []
        self.norms: list[ParsedNorm] = []
        self._spec_cache: dict[str, str] = {}
        self._parse_constraints()
        self._parse_norms()
        self.mission_constraints = [c for c in self.constraints if c.mission]
        self.scope: dict[str, list[ParsedConstraint]] = {gid: [] for gid in self.goals}
        for constraint in self.constraints:
            targets = self.goals if constraint.mission else constraint.goals
            for gid in targets:
                if gid in self.scope:
                    self.scope[gid].append(constraint)
        self._items: dict[str, Item] = {}
        self.permissions = [n for n in self.norms if n.modality == "permitted"]
        self._breaches: dict[str, Expr] = {}
        self._relevant: dict[tuple[str | None, str | None], list[ParsedNorm]] = {}
        self._residual: dict[tuple[str, str | None, str | None], bool] = {}
        self._scope_reads: dict[str, Reads] = {}
        # One z3 session per version of the orders, shared by check_logic and
        # check_properties; runs that use it hold the lock.
        self.session: Session | None = None
        self.lock = threading.RLock()

    # Parsing -----------------------------------------------------------------------------

    def parse_condition(self, text: str, label: str, subject: str, field_name: str,
                        sink: list[Finding] | None = None) -> Expr | None:
        """The checked tree of a condition, or None after adding an EXPR finding to `sink`
        (by default the model's own list)."""
        try:
            expr = parse(text)
            self.checker.condition(expr)
        except ExprError as exc:
            (self.expr_findings if sink is None else sink).append(
                error(
                    "EXPR",
                    [subject],
                    exc.located(label),
                    field=field_name,
                    column=exc.column,
                    expression=text[:500],
                )
            )
            return None
        return expr

    def _parse_constraints(self) -> None:
        seen: dict[str, int] = {}
        for constraint in self.orders.constraints:
            if constraint.expr is None:
                continue
            expr = self.parse_condition(constraint.expr, constraint.id, constraint.id, "expr")
            if expr is None:
                continue
            count = seen.get(constraint.id, 0)
            seen[constraint.id] = count + 1
            key = f"con:{constraint.id}" + (f"#{count}" if count else "")
            mission = constraint.applies_to == "mission"
            goals = frozenset() if mission else frozenset(constraint.applies_to)
            self.constraints.append(
                ParsedConstraint(
                    constraint.id, key, constraint.text, constraint.expr, expr, reads(expr),
                    mission, goals,
                )
            )

    def _norm_context(self, norm: Norm) -> tuple[Expr | None, str | None]:
        text = norm.context.strip()
        known_tags = {tag for area in self.orders.areas for tag in area.contexts}
        if text in known_tags or (
            _IDENTIFIER.fullmatch(text)
            and text not in self.quantities
            and text.lower() not in RESERVED
        ):
            return Context(text, 1), text
        return self.parse_condition(norm.context, f"{norm.id} context", norm.id, "context"), None

    def _parse_norms(self) -> None:
        seen: dict[str, int] = {}
        for norm in self.orders.norms:
            context, tag = self._norm_context(norm)
            modality: Literal["forbidden", "obligated", "permitted"]
            if norm.forbidden:
                modality, text = "forbidden", norm.forbidden
            elif norm.obligated:
                modality, text = "obligated", norm.obligated
            else:
                modality, text = "permitted", norm.permitted or ""
            body = self.parse_condition(text, f"{norm.id} {modality}", norm.id, modality)
            if context is None or body is None:
                continue
            count = seen.get(norm.id, 0)
            seen[norm.id] = count + 1
            key = f"norm:{norm.id}" + (f"#{count}" if count else "")
            self.norms.append(
                ParsedNorm(norm, key, modality, context, tag, body,
                           _merge_reads([reads(context), reads(body)]))
            )

    # Words -------------------------------------------------------------------------------

    def spec(self, name: str) -> str:
        """A quantity's declaration as text, for cache keys."""
        cached = self._spec_cache.get(name)
        if cached is None:
            q = self.quantities.get(name) or Quantity()
            cached = f"{name}:{q.type}:{q.unit}:{q.min}:{q.max}:{q.title}"
            self._spec_cache[name] = cached
        return cached

    def specs(self, names: Iterable[str]) -> str:
        return ",".join(self.spec(n) for n in sorted(names))

    def words(self, expr: Expr) -> str:
        text = describe(expr, self.quantities)
        return text if len(text) <= MAX_WORDS else text[:MAX_WORDS - 5].rstrip() + " ..."

    def unit(self, name: str) -> str:
        spec = self.quantities.get(name)
        return spec.unit if spec is not None else ""

    @staticmethod
    def goal_label(goal: Goal) -> str:
        return f"{goal.id} {goal.title}" if goal.title else goal.id

    def area_label(self, area_id: str) -> str:
        area = self.areas.get(area_id)
        return area.title if area is not None and area.title else f"area {area_id}"

    def vehicle_label(self) -> str:
        if self.vehicle is None:
            return "the vehicle"
        return f"the vehicle {self.vehicle.title or self.vehicle.id}"

    def scope_reads(self, goal_id: str) -> Reads:
        """What the constraints in a goal's scope read together (a superset when some are
        quarantined, which only adds harmless facts and bounds)."""
        found = self._scope_reads.get(goal_id)
        if found is None:
            found = self._scope_reads[goal_id] = _merge_reads(
                c.reads for c in self.scope.get(goal_id, ()))
        return found

    def facts(self, goal: Goal) -> Facts:
        area = self.areas.get(goal.area) if goal.area else None
        return Facts(goal.behavior, goal.area, frozenset(area.contexts) if area else frozenset())

    # Items -------------------------------------------------------------------------------

    def _memo(self, key: str, build: Callable[[], Item]) -> Item:
        item = self._items.get(key)
        if item is None:
            item = self._items[key] = build()
        return item

    def constraint_item(self, c: ParsedConstraint, suffix: str = "", negate: bool = False) -> Item:
        key = ("neg:" if negate else "") + c.key + suffix

        def build() -> Item:
            return Item(
                key, "negation" if negate else "constraint", c.id,
                lambda: f"{c.id} requires {self.words(c.expr)}",
                f"{key}|{c.source}|{c.text}|{self.specs(c.reads.quantities)}",
                _with_suffix(expr_formula(c.expr, negate), suffix),
                shared=not suffix, quantities=tuple(sorted(c.reads.quantities)),
            )

        return self._memo(key, build)

    def envelope_item(self, goal: Goal, name: str, suffix: str = "") -> Item:
        key = f"env:{goal.id}:{name}{suffix}"

        def build() -> Item:
            low, high = goal.envelope[name]
            spec = self.quantities.get(name) or Quantity()

            def phrase() -> str:
                words = quantity_words(name, self.quantities)
                if spec.type == "boolean":
                    value = "true" if low > 0 else "false" if high < 1 else "true or false"
                    return f"{self.goal_label(goal)} is ordered with {words} {value}"
                return (f"{self.goal_label(goal)} is ordered at {words} "
                        f"{_range_words(low, high, spec.unit)}")

            return Item(
                key, "envelope", goal.id, phrase,
                f"{key}|{goal.title}|{low!r}|{high!r}|{self.spec(name)}",
                _with_suffix(_interval_formula(name, spec, low, high), suffix),
                shared=False, quantities=(name,),
            )

        return self._memo(key, build)

    def vehicle_item(self, name: str, suffix: str = "") -> Item | None:
        if self.vehicle is None or name not in self.vehicle.envelope:
            return None
        vehicle = self.vehicle
        key = f"veh:{vehicle.id}:{name}{suffix}"

        def build() -> Item:
            low, high = vehicle.envelope[name]
            spec = self.quantities.get(name) or Quantity()

            def phrase() -> str:
                return (f"{self.vehicle_label()} is limited to "
                        f"{quantity_words(name, self.quantities)} "
                        f"{_range_words(low, high, spec.unit)}")

            return Item(
                key, "vehicle", vehicle.id, phrase,
                f"{key}|{vehicle.title}|{low!r}|{high!r}|{self.spec(name)}",
                _with_suffix(_interval_formula(name, spec, low, high), suffix),
                shared=not suffix, quantities=(name,),
            )

        return self._memo(key, build)

    def domain_item(self, name: str, suffix: str = "") -> Item | None:
        spec = self.quantities.get(name)
        if spec is None or spec.type == "boolean" or (spec.min is None and spec.max is None):
            return None
        key = f"dom:{name}{suffix}"

        def phrase() -> str:
            assert spec is not None
            words = quantity_words(name, self.quantities)
            if spec.min is not None and spec.max is not None:
                return f"{words} always lies within {_range_words(spec.min, spec.max, spec.unit)}"
            if spec.min is not None:
                return f"{words} is never below {with_unit(number_words(spec.min), spec.unit)}"
            assert spec.max is not None
            return f"{words} is never above {with_unit(number_words(spec.max), spec.unit)}"

        def build() -> Item:
            assert spec is not None
            return Item(
                key, "domain", name, phrase, f"{key}|{self.spec(name)}",
                _with_suffix(_interval_formula(name, spec, spec.min, spec.max), suffix),
                shared=not suffix, quantities=(name,),
            )

        return self._memo(key, build)

    def background(self, names: Iterable[str], suffix: str = "") -> list[Item]:
        """Vehicle envelope and domain items of some quantities."""
        items: list[Item] = []
        for name in sorted(set(names)):
            for item in (self.vehicle_item(name, suffix), self.domain_item(name, suffix)):
                if item is not None:
                    items.append(item)
        return items

    def fact_items(self, goal: Goal, needs: Reads, suffix: str = "") -> list[Item]:
        items: list[Item] = []
        label = self.goal_label(goal)
        if needs.behavior:
            key = f"beh:{goal.id}{suffix}"

            def behavior() -> Item:
                code_of = goal.behavior
                return Item(
                    key, "behavior", goal.id,
                    lambda: (f"{label} has behavior {goal.behavior!r}" if goal.behavior
                             else f"{label} names no behavior"),
                    f"{key}|{goal.title}|{goal.behavior}",
                    _with_suffix(
                        lambda t: f"(= {t.special('behavior')} {smt_int(t.string_code(code_of))})",
                        suffix,
                    ),
                    shared=False,
                )

            items.append(self._memo(key, behavior))
        if needs.area:
            key = f"area:{goal.id}{suffix}"

            def area() -> Item:
                code_of = goal.area
                return Item(
                    key, "area", goal.id,
                    lambda: (f"{label} runs in {self.area_label(goal.area)}" if goal.area
                             else f"{label} names no area"),
                    f"{key}|{goal.title}|{goal.area}|{self.area_label(goal.area or '')}",
                    _with_suffix(
                        lambda t: f"(= {t.special('area')} {smt_int(t.string_code(code_of))})",
                        suffix,
                    ),
                    shared=False,
                )

            items.append(self._memo(key, area))
        facts = self.facts(goal)
        for tag in sorted(needs.tags):
            key = f"ctx:{goal.id}:{tag}{suffix}"
            holds = tag in facts.tags

            def context(tag: str = tag, holds: bool = holds, key: str = key) -> Item:
                def phrase() -> str:
                    if goal.area:
                        return f"{self.area_label(goal.area)} {tag_state(tag, holds)}"
                    return f"{label} names no area, so it is not {in_tag(tag)}"

                return Item(
                    key, "context", goal.area or goal.id, phrase,
                    f"{key}|{goal.title}|{goal.area}|{self.area_label(goal.area or '')}|{holds}",
                    _with_suffix(
                        lambda t: t.context(tag) if holds else f"(not {t.context(tag)})", suffix
                    ),
                    shared=False,
                )

            items.append(self._memo(key, context))
        return items

    # Norms -------------------------------------------------------------------------------

    def _where(self, n: ParsedNorm) -> str:
        if n.tag is not None:
            return in_tag(n.tag)
        return f"when {self.words(n.context)}"

    def _object(self, n: ParsedNorm) -> str:
        body = n.body
        if (isinstance(body, Compare) and body.ops == ("==",)
                and isinstance(body.operands[0], Special) and body.operands[0].name == "behavior"
                and isinstance(body.operands[1], Text)):
            return f"the behavior {body.operands[1].value!r}"
        return self.words(body)

    def norm_phrase(self, n: ParsedNorm) -> str:
        verb = {"forbidden": "forbids", "obligated": "requires", "permitted": "permits"}
        return f"{n.norm.id} {verb[n.modality]} {self._object(n)} {self._where(n)}"

    def breach_expr(self, n: ParsedNorm) -> Expr:
        """The states that break a norm: the context with the forbidden state, or the context
        without the obligated one. A permission that applies is an exception to a prohibition
        (every permission of the orders is considered; one whose context does not hold for a
        goal excuses nothing there)."""
        found = self._breaches.get(n.key)
        if found is not None:
            return found
        if n.modality == "obligated":
            breach: Expr = Logic("and", (n.context, Not(n.body, 1)), 1)
        else:
            operands: list[Expr] = [n.context, n.body]
            for p in self.permissions:
                operands.append(Not(Logic("and", (p.context, p.body), 1), 1))
            breach = Logic("and", tuple(operands), 1)
        self._breaches[n.key] = breach
        return breach

    def relevant_norms(self, goal: Goal) -> list[ParsedNorm]:
        """Prohibitions and obligations that the goal's facts do not already rule out."""
        key = (goal.behavior, goal.area)
        found = self._relevant.get(key)
        if found is None:
            facts = self.facts(goal)
            found = [n for n in self.norms if n.modality != "permitted"
                     and fold(self.breach_expr(n), facts) is not False]
            self._relevant[key] = found
        return found

    def residual(self, n: ParsedNorm, goal: Goal) -> bool:
        """Whether a breach of the norm depends on quantities (not decided by facts alone)."""
        key = (n.key, goal.behavior, goal.area)
        found = self._residual.get(key)
        if found is None:
            found = self._residual[key] = fold(self.breach_expr(n), self.facts(goal)) is None
        return found

    def norm_items(self, n: ParsedNorm) -> tuple[Item, Item]:
        """(the norm as a rule: no breach, the breach itself) for one norm."""
        def build_rule() -> Item:
            permissions = self.permissions if n.modality == "forbidden" else []
            quantities = tuple(sorted(_merge_reads(
                [n.reads, *(p.reads for p in permissions)]).quantities))
            exceptions = "".join(
                f"|{p.norm.id}:{p.norm.context}:{p.norm.permitted}" for p in permissions
            )
            source = (f"{n.key}|{n.norm.context}|{n.modality}|{getattr(n.norm, n.modality)}|"
                      f"{n.norm.text}{exceptions}|{self.specs(quantities)}")

            def phrase() -> str:
                words = self.norm_phrase(n)
                if permissions:
                    words += " (unless " + " or ".join(
                        self.norm_phrase(p) for p in permissions) + ")"
                return words

            return Item(n.key, "norm", n.norm.id, phrase, source,
                        expr_formula(self.breach_expr(n), negate=True), quantities=quantities)

        rule = self._memo(n.key, build_rule)
        breach_key = f"breach:{n.key}"
        broken = self._memo(breach_key, lambda: Item(
            breach_key, "breach", n.norm.id, lambda: rule.phrase, "breach|" + rule.source,
            expr_formula(self.breach_expr(n)), quantities=rule.quantities,
        ))
        return rule, broken

    def norm_reads(self, n: ParsedNorm) -> Reads:
        if n.modality != "forbidden":
            return n.reads
        return _merge_reads([n.reads, *(p.reads for p in self.permissions)])


# ---------------------------------------------------------------------------------------------
# Solver session: one z3 context, incremental, items behind indicator literals.


@dataclass
class Limits:
    per_call_ms: int
    deadline: float

    @classmethod
    def start(cls, per_call_ms: int, total_s: float) -> Limits:
        return cls(per_call_ms, time.monotonic() + total_s)

    def remaining_ms(self) -> int:
        return int((self.deadline - time.monotonic()) * 1000)


@dataclass(frozen=True)
class CheckResult:
    status: Literal["sat", "unsat", "unknown"]
    core: tuple[Item, ...] = ()
    reason: str = ""


class Session:
    """A z3 context and an incremental solver. Shared items are asserted once at the base
    level; goal-specific items inside a push/pop scope."""

    def __init__(self, quantities: dict[str, Quantity], limits: Limits) -> None:
        z3 = _z3()
        self.z3 = z3
        self.ctx = z3.Context()
        self.solver = z3.SimpleSolver(ctx=self.ctx)
        self.limits = limits
        self.translator = Translator(quantities)
        self._timeout: int | None = None
        self._declared_symbols = 0
        self._indicators: dict[str, str] = {}
        self._literals: dict[str, Any] = {}
        self._ids: dict[str, int] = {}
        self._based: set[str] = set()
        self._items: dict[str, Item] = {}
        self.in_scope = False
        self._batches = 0
        self.calls = 0
        self.undecided = False

    def _indicator(self, item: Item) -> tuple[str, bool]:
        name = self._indicators.get(item.key)
        if name is not None:
            return name, False
        name = f"a:{len(self._indicators)}"
        self._indicators[item.key] = name
        return name, True

    def _assert(self, items: Iterable[Item]) -> None:
        chunks: list[str] = []
        for item in items:
            name, new = self._indicator(item)
            self._items[name] = item
            formula = item.formula(self.translator)
            if new:
                chunks.append(f"(declare-const |{name}| Bool)")
            chunks.append(f"(assert (=> |{name}| {formula}))")
        symbols = self.translator.symbols
        if len(symbols) > self._declared_symbols:
            fresh = list(symbols.items())[self._declared_symbols:]
            self._declared_symbols = len(symbols)
            chunks.insert(0, "".join(f"(declare-const {s} {sort})" for s, sort in fresh))
        if chunks:
            self.solver.from_string("".join(chunks))

    @contextmanager
    def scope(self, items: Iterable[Item]) -> Iterator[None]:
        """Make items checkable: shared ones permanently, the others until the scope ends."""
        assert not self.in_scope
        items = list(items)
        shared = [i for i in items if i.shared and i.key not in self._based]
        if shared:
            self._assert(shared)
            self._based.update(i.key for i in shared)
        self.solver.push()
        self.in_scope = True
        try:
            self._assert(i for i in items if not i.shared)
            yield
        finally:
            self.solver.pop()
            self.in_scope = False

    def _literal(self, item: Item) -> Any:
        name = self._indicators[item.key]
        literal = self._literals.get(name)
        if literal is None:
            literal = self._literals[name] = self.z3.Bool(name, self.ctx)
            self._ids[item.key] = literal.get_id()
        return literal

    def check(self, items: Sequence[Item]) -> CheckResult:
        z3 = self.z3
        remaining = self.limits.remaining_ms()
        if remaining <= 0:
            self.undecided = True
            return CheckResult("unknown", reason="time budget exhausted")
        timeout = max(1, min(self.limits.per_call_ms, remaining))
        if timeout != self._timeout:
            self.solver.set("timeout", timeout)
            self._timeout = timeout
        self.calls += 1
        literals = [self._literal(i) for i in items]
        # The C call directly (z3_adapter): the wrapper's own checks cost more than solving.
        try:
            status = check_assumptions(z3, self.ctx, self.solver, literals)
        except z3.Z3Exception as exc:  # pragma: no cover - defensive: never crash a report
            self.undecided = True
            return CheckResult("unknown", reason=f"solver error: {exc}")
        if status == "sat":
            return CheckResult("sat")
        if status == "unsat":
            ids = {literal.get_id() for literal in self.solver.unsat_core()}
            core = tuple(i for i in items if self._ids[i.key] in ids)
            return CheckResult("unsat", core or tuple(items))
        self.undecided = True
        reason = self.solver.reason_unknown()
        if reason in {"canceled", "timeout"}:
            reason = f"timeout after {timeout:,} ms"
        return CheckResult("unknown", reason=reason)

    def satisfiable_groups(self, groups: Sequence[Sequence[Item]]) -> list[bool]:
        """Which groups of items are shown satisfiable (each on its own), with few checks:
        ask for a model of "some group holds", mark every group that model satisfies, and
        ask again for the rest. False means not shown (unsatisfiable or undecided): the caller
        checks those one by one, so results are those of one check per group."""
        shown = [False] * len(groups)
        if not groups or self.limits.remaining_ms() <= 0:
            return shown
        assert not self.in_scope
        z3 = self.z3
        formulas = []
        for group in groups:
            parts = [item.formula(self.translator) for item in group]
            formulas.append(parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})")
        base = self._batches
        self._batches += len(groups)
        names = [f"|v:{base + i}|" for i in range(len(groups))]
        # Declarations at the base level (they assert nothing), definitions inside the scope.
        symbols = self.translator.symbols
        chunks = [f"(declare-const {s} {sort})"
                  for s, sort in list(symbols.items())[self._declared_symbols:]]
        self._declared_symbols = len(symbols)
        chunks.extend(f"(declare-const {name} Bool)" for name in names)
        self.solver.from_string("".join(chunks))
        literals = [z3.Bool(name.strip("|"), self.ctx) for name in names]
        self.solver.push()
        try:
            self.solver.from_string("".join(
                f"(assert (= {name} {formula}))"
                for name, formula in zip(names, formulas, strict=True)
            ))
            pending = list(range(len(groups)))
            while pending:
                remaining = self.limits.remaining_ms()
                if remaining <= 0:
                    break
                timeout = max(1, min(self.limits.per_call_ms, remaining))
                if timeout != self._timeout:
                    self.solver.set("timeout", timeout)
                    self._timeout = timeout
                self.calls += 1
                self.solver.push()
                try:
                    self.solver.add(z3.Or([literals[i] for i in pending]))
                    if self.solver.check() != z3.sat:
                        break
                    model = self.solver.model()
                    found = [i for i in pending
                             if z3.is_true(model.eval(literals[i], model_completion=True))]
                finally:
                    self.solver.pop()
                if not found:  # pragma: no cover - a model of the disjunction satisfies one
                    break
                for i in found:
                    shown[i] = True
                pending = [i for i in pending if not shown[i]]
        finally:
            self.solver.pop()
        return shown

    def witness(self, quantities: Iterable[str], suffix: str = "") -> dict[str, str]:
        """Values of some quantities in the model of the last satisfiable check."""
        z3 = self.z3
        model = self.solver.model()
        translator = self.translator.with_suffix(suffix)
        values: dict[str, str] = {}
        for name in quantities:
            symbol, kind = translator.quantity(name)
            sort = {"boolean": z3.BoolSort(self.ctx), "integer": z3.IntSort(self.ctx)}.get(
                kind, z3.RealSort(self.ctx)
            )
            value = model.eval(z3.Const(symbol.strip("|"), sort), model_completion=True)
            if kind == "boolean":
                values[name] = "true" if z3.is_true(value) else "false"
            elif kind == "integer":
                values[name] = str(value.as_long())
            else:
                values[name] = _decimal(value)
        return values

    # Minimal cores (seed 001, Algorithm 1) ---------------------------------------------------

    def minimal_core(self, core: Sequence[Item], hard: Sequence[Item] = ()) -> tuple[
        list[Item], bool
    ]:
        """A minimal subset M of `core` with `hard` + M unsatisfiable, given that `hard` alone
        is satisfiable and `hard` + `core` is not. Returns (M, proven minimal)."""
        self.undecided = False
        found = self._minimise(list(core), list(hard))
        return found, not self.undecided

    def _minimise(self, s: list[Item], s0: list[Item]) -> list[Item]:
        # Algorithm 1: split S in two halves S' and S''. If either half is already
        # unsatisfiable with S0, recurse into it; otherwise each half needs part of the other:
        # minimise S' against S0 + S'', then S'' against S0 + S'min.
        if len(s) <= 1:
            return s
        half = len(s) // 2
        first, second = s[:half], s[half:]
        result = self.check([*s0, *first])
        if result.status == "unsat":
            inside = [i for i in first if i in result.core]
            return self._minimise(inside, s0) if inside else []
        result = self.check([*s0, *second])
        if result.status == "unsat":
            inside = [i for i in second if i in result.core]
            return self._minimise(inside, s0) if inside else []
        first_min = self._minimise(first, [*s0, *second])
        second_min = self._minimise(second, [*s0, *first_min])
        return first_min + second_min


def _decimal(value: Any) -> str:
    try:
        fraction = Fraction(value.numerator_as_long(), value.denominator_as_long())
    except Exception:  # algebraic numbers from nonlinear problems
        return str(value.as_decimal(6)).rstrip("?")
    return number_words(fraction)


# ---------------------------------------------------------------------------------------------
# Cache


class LogicCache:
    """Unit results by the digest of their inputs; thread-safe and bounded (least recently used
    entries go first). Hold one per process (or per editing session) and pass it to every
    call: a unit whose items did not change is never solved again."""

    def __init__(self, max_entries: int = 100_000) -> None:
        self._data: OrderedDict[str, object] = OrderedDict()
        self._lock = threading.Lock()
        self.max_entries = max_entries
        self.hits = 0
        self.misses = 0
        self._last: tuple[Orders, LogicModel] | None = None

    def model(self, orders: Orders) -> LogicModel:
        """The parsed model of these very orders (the same object) if the last call built it:
        check_logic and check_properties on one version of the orders parse it once."""
        with self._lock:
            last = self._last
        if last is not None and last[0] is orders:
            return last[1]
        model = LogicModel(orders)
        with self._lock:
            self._last = (orders, model)
        return model

    def get(self, key: str) -> object | None:
        with self._lock:
            value = self._data.get(key)
            if value is None:
                self.misses += 1
            else:
                self.hits += 1
                self._data.move_to_end(key)
            return value

    def put(self, key: str, value: object) -> None:
        with self._lock:
            self._data[key] = value
            self._data.move_to_end(key)
            while len(self._data) > self.max_entries:
                self._data.popitem(last=False)

    def __len__(self) -> int:
        return len(self._data)

    def clear(self) -> None:
        with self._lock:
            self._data.clear()
            self.hits = self.misses = 0
            self._last = None


def unit_key(kind: str, items: Iterable[Item]) -> str:
    """The digest of a unit's inputs: the digests of its items' sources, in a fixed order."""
    digests = sorted(item.digest for item in items)
    return hashlib.sha256(f"{VERSION}\x1e{kind}\x1e".encode() + b"".join(digests)).hexdigest()


# ---------------------------------------------------------------------------------------------
# Unit results (what the cache holds)


@dataclass(frozen=True)
class Core:
    parts: tuple[Part, ...]
    minimal: bool

    def to_json(self) -> list[dict[str, str]]:
        return [p.to_json() for p in self.parts]


@dataclass(frozen=True)
class MissionResult:
    cores: tuple[Core, ...]
    quarantined: frozenset[str]
    undecided: str | None


@dataclass(frozen=True)
class Risk:
    norm: Part
    witness: tuple[tuple[str, str], ...]


@dataclass(frozen=True)
class GoalResult:
    contradictions: tuple[Core, ...]
    refusals: tuple[Core, ...]
    risks: tuple[Risk, ...]
    undecided: str | None


@dataclass(frozen=True)
class VacuousResult:
    core: Core | None
    undecided: str | None


# ---------------------------------------------------------------------------------------------
# The run: units, the cache and one lazily created session


class LogicRun:
    """One run of checks: the units, the cache and the model's z3 session."""

    def __init__(self, model: LogicModel, cache: LogicCache | None, limits: Limits) -> None:
        self.model = model
        self.cache = cache if cache is not None else LogicCache()
        self.limits = limits
        self._session: Session | None = None
        self.solved_units = 0

    @property
    def session(self) -> Session:
        """The model's z3 session (one per version of the orders), under this run's limits.
        Callers hold `model.lock` for the whole run."""
        if self._session is None:
            session = self.model.session
            if session is None:
                session = self.model.session = Session(self.model.quantities, self.limits)
            session.limits = self.limits
            self._session = session
        return self._session

    def cached(self, kind: str, items: Iterable[Item], solve: Callable[[], Any]) -> Any:
        key = unit_key(kind, items)
        found = self.cache.get(key)
        if found is not None:
            return found
        self.solved_units += 1
        result = solve()
        # What a timeout cut short (undecided, or a core not proven minimal) is tried again.
        cores = [c for name in ("cores", "contradictions", "refusals", "core")
                 for c in _as_tuple(getattr(result, name, ()))]
        if getattr(result, "undecided", None) is None and all(c.minimal for c in cores):
            self.cache.put(key, result)
        return result

    def cores(self, items: list[Item], drop: Callable[[list[Item]], list[Item]],
              limit: int = MAX_CORES_PER_UNIT) -> tuple[list[Core], list[Item], str | None]:
        """Minimal cores of an item set, dropping items after each so that independent
        contradictions are all found (up to a limit). Returns (cores, remaining, undecided)."""
        session = self.session
        found: list[Core] = []
        result = session.check(items)
        while result.status == "unsat" and len(found) < limit:
            core, minimal = session.minimal_core(result.core)
            if not core:
                break
            found.append(Core(tuple(sorted_parts(core)), minimal))
            removed = drop(core)
            if not removed:
                break
            items = [i for i in items if i not in removed]
            result = session.check(items)
        undecided = result.reason if result.status == "unknown" else None
        return found, items, undecided

    # Mission -------------------------------------------------------------------------------

    def mission(self) -> MissionResult:
        model = self.model
        names: set[str] = set(model.vehicle.envelope) if model.vehicle else set()
        for c in model.mission_constraints:
            names |= c.reads.quantities
        items = model.background(names) + [model.constraint_item(c)
                                           for c in model.mission_constraints]
        result: MissionResult = self.cached("mission", items, lambda: self._solve_mission(items))
        return result

    def _solve_mission(self, items: list[Item]) -> MissionResult:
        def drop(core: list[Item]) -> list[Item]:
            return [i for i in core if i.kind == "constraint"] or [
                i for i in core if i.kind == "vehicle"] or core

        with self.session.scope(items):
            cores, remaining, undecided = self.cores(items, drop, limit=5)
        quarantined = frozenset(i.key for i in items if i not in remaining)
        return MissionResult(tuple(cores), quarantined, undecided)

    # Goals ---------------------------------------------------------------------------------

    def goal_items(self, goal: Goal, quarantined: frozenset[str],
                   extra: Sequence[Reads] = ()) -> tuple[list[Item], list[ParsedConstraint]]:
        """The statements that hold while a goal runs as ordered: its envelope, the facts that
        expressions read, the constraints in scope, the vehicle envelope and the domains."""
        model = self.model
        constraints = [c for c in model.scope.get(goal.id, ()) if c.key not in quarantined]
        needs = _merge_reads([model.scope_reads(goal.id), *extra])
        names = set(goal.envelope) | needs.quantities
        items = [model.envelope_item(goal, name) for name in sorted(goal.envelope)]
        items += model.fact_items(goal, needs)
        items += [model.constraint_item(c) for c in constraints]
        items += [i for i in model.background(names) if i.key not in quarantined]
        return items, constraints

    def goal(self, goal: Goal, quarantined: frozenset[str]) -> GoalResult:
        model = self.model
        norms = model.relevant_norms(goal)
        items, _ = self.goal_items(goal, quarantined, [model.norm_reads(n) for n in norms])
        norm_items = [model.norm_items(n) for n in norms]
        residual = [pair for n, pair in zip(norms, norm_items, strict=True)
                    if model.residual(n, goal)]
        every = items + [i for pair in norm_items for i in pair]
        result: GoalResult = self.cached(
            "goal", every, lambda: self._solve_goal(items, norm_items, residual)
        )
        return result

    def _solve_goal(self, items: list[Item], norm_items: list[tuple[Item, Item]],
                    residual: list[tuple[Item, Item]]) -> GoalResult:
        session = self.session
        every = items + [i for pair in norm_items for i in pair]

        def drop_contradiction(core: list[Item]) -> list[Item]:
            return [i for i in core if i.kind == "constraint"] or [
                i for i in core if i.kind == "envelope"] or core

        def drop_norms(core: list[Item]) -> list[Item]:
            return [i for i in core if i.kind == "norm"] or core

        rules = [rule for rule, _ in norm_items]
        refusals: list[Core] = []
        undecided: str | None = None
        with session.scope(every):
            # Most goals are fine: one check of everything settles both questions.
            together = session.check(items + rules) if rules else None
            if together is None or together.status != "sat":
                contradictions, _, undecided = self.cores(items, drop_contradiction)
                if contradictions or undecided is not None or not rules:
                    return GoalResult(tuple(contradictions), (), (), undecided)
                refusals, _, undecided = self.cores(items + rules, drop_norms,
                                                    limit=len(rules))
            refused = {i.key for core in refusals for i in core.parts}
            risks: list[Risk] = []
            for rule, breach in residual:
                if rule.key in refused or undecided is not None:
                    continue
                result = session.check([*items, breach])
                if result.status == "sat":
                    witness = session.witness(breach.quantities)
                    risks.append(Risk(rule.part, tuple(sorted(witness.items()))))
                elif result.status == "unknown":
                    undecided = result.reason
        return GoalResult((), tuple(refusals), tuple(risks), undecided)

    # Vacuous constraints -------------------------------------------------------------------

    def vacuous_batch(self, constraints: Iterable[ParsedConstraint]) -> None:
        """Settle the constraints whose negation can hold with few solver checks (one model
        serves many), caching the same result one check each would give; the others (the
        vacuous and the undecided) are left for `vacuous`."""
        model = self.model
        pending: list[tuple[str, list[Item]]] = []
        for c in constraints:
            items = [model.constraint_item(c, negate=True), *model.background(c.reads.quantities)]
            key = unit_key("vacuous", items)
            if self.cache.get(key) is None:
                pending.append((key, items))
        if len(pending) < 2:
            return
        shown = self.session.satisfiable_groups([items for _, items in pending])
        for (key, _), sat in zip(pending, shown, strict=True):
            if sat:
                self.solved_units += 1
                self.cache.put(key, VacuousResult(None, None))

    def vacuous(self, c: ParsedConstraint) -> VacuousResult:
        model = self.model
        negation = model.constraint_item(c, negate=True)
        items = [negation, *model.background(c.reads.quantities)]
        result: VacuousResult = self.cached("vacuous", items, lambda: self._solve_vacuous(items))
        return result

    def _solve_vacuous(self, items: list[Item]) -> VacuousResult:
        session = self.session
        with session.scope(items):
            result = session.check(items)
            if result.status == "unknown":
                return VacuousResult(None, result.reason)
            if result.status == "sat" or items[0] not in result.core:
                return VacuousResult(None, None)
            core, minimal = session.minimal_core(result.core)
        if items[0] not in core:
            return VacuousResult(None, None)
        return VacuousResult(Core(tuple(sorted_parts(core)), minimal), None)


def _as_tuple(value: object) -> tuple[Core, ...]:
    if isinstance(value, Core):
        return (value,)
    return tuple(c for c in value if isinstance(c, Core)) if isinstance(value, tuple) else ()


def sorted_parts(items: Iterable[Item]) -> list[Part]:
    return [i.part for i in sorted(items, key=lambda i: (_KIND_ORDER.get(i.kind, 9), i.key))]


# ---------------------------------------------------------------------------------------------
# Sentences


def join_words(phrases: Sequence[str]) -> str:
    if len(phrases) <= 1:
        return "".join(phrases)
    return ", ".join(phrases[:-1]) + " and " + phrases[-1]


def core_sentence(parts: Sequence[Part]) -> str:
    """'<what the goal is ordered to do>, but <what forbids it>.'"""
    lead = [p for p in parts if p.kind in GOAL_KINDS]
    rest = [p for p in parts if p.kind not in GOAL_KINDS]
    if not lead:
        lead, rest = rest[:1], rest[1:]
    text = join_words(_merged(lead))
    text += ", but " + join_words([p.phrase for p in rest]) if rest else ", which can never hold"
    return text[:1].upper() + text[1:] + "."


def _merged(parts: Sequence[Part]) -> list[str]:
    """Phrases, with a goal's later envelope bounds shortened: 'G1 is ordered at depth 0-5 m
    and distance to the nearest shipping lane 0-500 m'."""
    phrases: list[str] = []
    seen: set[str] = set()
    for part in parts:
        marker = " is ordered at "
        if part.kind == "envelope" and part.subject in seen and marker in part.phrase:
            phrases.append(part.phrase.split(marker, 1)[1])
            continue
        if part.kind == "envelope":
            seen.add(part.subject)
        phrases.append(part.phrase)
    return phrases


def _subjects(first: Sequence[str], parts: Iterable[Part], kinds: Iterable[str] | None = None
              ) -> list[str]:
    subjects = list(dict.fromkeys(first))
    wanted = set(kinds) if kinds is not None else None
    for part in parts:
        if (wanted is None or part.kind in wanted) and part.subject not in subjects:
            subjects.append(part.subject)
    return subjects


def _ids(parts: Iterable[Part], kind: str) -> list[str]:
    return list(dict.fromkeys(p.subject for p in parts if p.kind == kind))


def _core_details(core: Core) -> dict[str, Any]:
    return {"core": core.to_json(), "minimal": core.minimal}


# ---------------------------------------------------------------------------------------------
# Public API


def check_logic(
    orders: Orders,
    cache: LogicCache | None = None,
    *,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
    total_timeout_s: float = DEFAULT_TOTAL_S,
) -> list[Finding]:
    """EXPR, CONTRADICTION, NORM and VACUOUS findings of a set of orders.

    Pass a long-lived LogicCache to re-solve only the units whose inputs changed. Every solver
    call stops after `timeout_ms`, and the whole check after `total_timeout_s`; what could not
    be decided is reported as a warning."""
    model = cache.model(orders) if cache is not None else LogicModel(orders)
    with model.lock:
        run = LogicRun(model, cache, Limits.start(timeout_ms, total_timeout_s))
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
    out_of_time: list[str] = []
    for goal in model.goals.values():
        result = run.goal(goal, mission.quarantined)
        label = model.goal_label(goal)
        for core in result.contradictions:
            if not any(p.kind in GOAL_KINDS for p in core.parts):
                key = tuple(p.key for p in core.parts)
                shared.setdefault(key, (core, []))[1].append(goal.id)
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
        for risk in result.risks:
            yield _risk(model, goal, risk)
        if result.undecided == "time budget exhausted":
            out_of_time.append(goal.id)
        elif result.undecided:
            scope = [c.id for c in model.scope.get(goal.id, ())]
            yield warning(
                "CONTRADICTION",
                [goal.id],
                f"The solver could not decide whether {label} can run as ordered under its "
                f"constraints and norms ({result.undecided}). Simplify the expressions that "
                f"apply to it{': ' + ', '.join(scope) if scope else ''}.",
                goal=goal.id,
                undecided=result.undecided,
            )
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
    if out_of_time:
        yield warning(
            "CONTRADICTION",
            out_of_time,
            f"The logic checks ran out of time before deciding {len(out_of_time)} goal(s): "
            f"{', '.join(out_of_time[:20])}{' ...' if len(out_of_time) > 20 else ''}.",
            undecided="time budget exhausted",
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
    for c in model.constraints:
        if c.key in mission.quarantined:
            continue
        result = run.vacuous(c)
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


# ---------------------------------------------------------------------------------------------
# Goal-set consistency (seed 001, section 5.4.2)


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
