"""The logic model of orders: every item of the mission, its goals and its norms."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import partial
from typing import Literal

from ...orders.findings import Finding, error
from ...orders.model import Goal, Norm, Orders, Quantity, Vehicle
from ..expressions import (
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
    TypeChecker,
    describe,
    fold,
    in_tag,
    number_words,
    parse,
    quantity_table,
    quantity_words,
    reads,
    with_unit,
)
from .constants import _IDENTIFIER, MAX_WORDS
from .facts import area_item, behavior_item, context_item
from .items import Item, _interval_formula, _range_words, _with_suffix, expr_formula
from .results import GoalOutcome
from .screen import Screen
from .session import Session
from .unique import UniqueCores

# True: every constraint stays asserted once a unit used it (the policy before, kept
# as the benchmark's baseline).
KEEP_EVERY_CONSTRAINT = False


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


@dataclass(frozen=True, slots=True)
class GoalItems:
    """A goal's items but the live mission-wide block (which every goal holds: one list for
    all): its envelope and facts (head), its own constraints' items, its background (tail)."""

    head: tuple[Item, ...]
    own: tuple[Item, ...]
    tail: tuple[Item, ...]
    own_constraints: tuple[ParsedConstraint, ...]


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


def _same_but_goals(one: Orders, other: Orders) -> bool:
    return one.model_extra == other.model_extra and all(
        getattr(one, name) == getattr(other, name)
        for name in type(one).model_fields if name != "goals")


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
        # Constraints named by goal; the mission-wide ones (in every goal's scope) are kept
        # once, not copied into thousands of lists.
        self.scoped: dict[str, list[ParsedConstraint]] = {gid: [] for gid in self.goals}
        for constraint in self.constraints:
            for gid in constraint.goals:
                if gid in self.scoped:
                    self.scoped[gid].append(constraint)
        self._mission_reads: Reads | None = None
        self._mission_block: dict[frozenset[str], tuple[list[ParsedConstraint],
                                                        list[Item]]] = {}
        self._items: dict[str, Item] = {}
        self.permissions = [n for n in self.norms if n.modality == "permitted"]
        self._breaches: dict[str, Expr] = {}
        self._relevant: dict[tuple[str | None, str | None], list[ParsedNorm]] = {}
        self._residual: dict[tuple[str, str | None, str | None], bool] = {}
        self._scope_reads: dict[str, Reads] = {}
        self._norm_reads: dict[str, Reads] = {}
        self._needs: dict[tuple[Reads, tuple[Reads, ...]], Reads] = {}
        # Built once per goal or set of quantities, then copied: every unit of a goal (its own
        # and one per state property) asks for the same lists. A goal's own part only: the
        # mission-wide block is one list for all (kept per goal, 10,000 copies of hundreds of
        # references were most of what each garbage collection walked).
        self._scope_own: dict[tuple[str, frozenset[str]], tuple[
            tuple[ParsedConstraint, ...], tuple[Item, ...]]] = {}
        self._background: dict[tuple[frozenset[str], str], tuple[Item, ...]] = {}
        # LogicRun.goal_items by (goal id, quarantined keys, extra reads), without the block.
        self.goal_items_memo: dict[tuple[str, frozenset[str], tuple[Reads, ...]],
                                   GoalItems] = {}
        # Which of them came from the model before (their items' phrases already worded).
        self._carried_items: set[tuple[str, frozenset[str], tuple[Reads, ...]]] = set()
        # check_logic's outcome of each goal by (goal id, quarantined keys), and the path
        # properties' verdict of each goal by (goal id, quarantined keys, property item key
        # and source): carried like the goal items, and used only while the cache still holds
        # the very result under its key.
        self.goal_outcomes: dict[tuple[str, frozenset[str]], GoalOutcome] = {}
        self.property_verdicts: dict[tuple[str, frozenset[str], str, str],
                                     tuple[str | None, object]] = {}
        # One z3 session per version of the orders, shared by check_logic and
        # check_properties; runs that use it hold the lock.
        self.session: Session | None = None
        # Its status-only checks (screen.py), made on first use like the session.
        self.screen: Screen | None = None
        # Cores proven the only ones without z3 (unique.py), made with the screen.
        self.unique_cores: UniqueCores | None = None
        self.lock = threading.RLock()

    def carry_goal_items(self, before: LogicModel) -> None:
        """Start with the goal items of the model of the orders before an edit, for each goal
        the edit left as it was, and with its norms by goal facts, when nothing else the
        items read changed (everything in the orders but the goals, and the quantity table,
        which goal envelopes extend): building the items of a thousand goals again was most
        of a one-goal edit's logic check.
        Each carried item's phrase is worded now, so that it no longer holds the model that
        built it: models would otherwise keep every model before them alive."""
        if before.quantities != self.quantities or not _same_but_goals(before.orders,
                                                                       self.orders):
            return
        # Which norms a goal's facts leave open reads the norms, areas and the goal's
        # behaviour and area only: every entry stays true.
        self._relevant.update(before._relevant.copy())
        self._residual.update(before._residual.copy())
        same = {gid for gid, goal in self.goals.items() if before.goals.get(gid) == goal}
        for memo, found in before.goal_items_memo.copy().items():
            if memo[0] in same:
                if memo not in before._carried_items:  # carried ones were worded then
                    for item in (*found.head, *found.own, *found.tail):
                        item.word()
                self.goal_items_memo.setdefault(memo, found)
                self._carried_items.add(memo)
        for outcome_memo, outcome in before.goal_outcomes.copy().items():
            if outcome_memo[0] in same:
                self.goal_outcomes.setdefault(outcome_memo, outcome)
        for verdict_memo, verdict in before.property_verdicts.copy().items():
            if verdict_memo[0] in same:
                self.property_verdicts.setdefault(verdict_memo, verdict)

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

    def in_scope(self, goal_id: str) -> list[ParsedConstraint]:
        """The constraints that apply while a goal runs, in the order of the orders."""
        scoped = self.scoped.get(goal_id, [])
        if not scoped:
            return list(self.mission_constraints)
        order = {c.key: n for n, c in enumerate(self.constraints)}
        return sorted([*self.mission_constraints, *scoped], key=lambda c: order[c.key])

    def scope_reads(self, goal_id: str) -> Reads:
        """What the constraints in a goal's scope read together (a superset when some are
        quarantined, which only adds harmless facts and bounds)."""
        found = self._scope_reads.get(goal_id)
        if found is None:
            if self._mission_reads is None:
                self._mission_reads = _merge_reads(c.reads for c in self.mission_constraints)
            found = self._scope_reads[goal_id] = _merge_reads(
                [self._mission_reads, *(c.reads for c in self.scoped.get(goal_id, ()))])
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
        found = self._items.get(key)  # every goal in scope asks: no closure for a known item
        if found is not None:
            return found

        def build() -> Item:
            return Item(
                key, "negation" if negate else "constraint", c.id,
                lambda: f"{c.id} requires {self.words(c.expr)}",
                f"{key}|{c.source}|{c.text}|{self.specs(c.reads.quantities)}",
                _with_suffix(expr_formula(c.expr, negate), suffix),
                # Only what every goal's checks assume stays in the solver: each check costs
                # time in proportion to all that is asserted, and a constraint scoped to a few
                # goals (or a negation, checked once) would tax every later goal's checks.
                shared=not suffix and (KEEP_EVERY_CONSTRAINT or (c.mission and not negate)),
                quantities=tuple(sorted(c.reads.quantities)),
                meaning=None if suffix else ("expr", ("con", c.source, negate), (c.expr, negate)),
            )

        return self._memo(key, build)

    def envelope_item(self, goal: Goal, name: str, suffix: str = "") -> Item:
        key = f"env:{goal.id}:{name}{suffix}"

        def build() -> Item:
            low, high = goal.envelope[name]
            spec = self.quantities.get(name) or Quantity()
            return Item(
                key, "envelope", goal.id, partial(self._envelope_phrase, goal, name),
                f"{key}|{goal.title}|{low!r}|{high!r}|{self.spec(name)}",
                _with_suffix(_interval_formula(name, spec, low, high), suffix),
                shared=False, quantities=(name,),
                meaning=None if suffix else ("box", name, low, high),
            )

        return self._memo(key, build)

    def _envelope_phrase(self, goal: Goal, name: str) -> str:
        # A method behind a partial, not a closure: one per envelope item (see items.py).
        low, high = goal.envelope[name]
        spec = self.quantities.get(name) or Quantity()
        words = quantity_words(name, self.quantities)
        if spec.type == "boolean":
            value = "true" if low > 0 else "false" if high < 1 else "true or false"
            return f"{self.goal_label(goal)} is ordered with {words} {value}"
        return (f"{self.goal_label(goal)} is ordered at {words} "
                f"{_range_words(low, high, spec.unit)}")

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
                meaning=None if suffix else ("box", name, low, high),
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
                meaning=None if suffix else ("box", name, spec.min, spec.max),
            )

        return self._memo(key, build)

    def background(self, names: Iterable[str], suffix: str = "") -> list[Item]:
        """Vehicle envelope and domain items of some quantities."""
        key = (frozenset(names), suffix)
        found = self._background.get(key)
        if found is None:
            items: list[Item] = []
            for name in sorted(key[0]):
                for item in (self.vehicle_item(name, suffix), self.domain_item(name, suffix)):
                    if item is not None:
                        items.append(item)
            found = self._background[key] = tuple(items)
        return list(found)

    def mission_block(self, quarantined: frozenset[str]) -> frozenset[Item]:
        """The items of the live mission-wide constraints: every goal's scope holds them."""
        return frozenset(self.live_block(quarantined)[1])

    def live_block(self, quarantined: frozenset[str]) -> tuple[list[ParsedConstraint],
                                                                list[Item]]:
        """The live mission-wide constraints and their items (lists not to be changed)."""
        block = self._mission_block.get(quarantined)
        if block is None:
            live = [c for c in self.mission_constraints if c.key not in quarantined]
            block = self._mission_block[quarantined] = (
                live, [self.constraint_item(c) for c in live])
        return block

    def scope_own(self, goal_id: str, quarantined: frozenset[str]) -> tuple[
        tuple[ParsedConstraint, ...], tuple[Item, ...]
    ]:
        """The live constraints scoped to the goal by name, and their items."""
        key = (goal_id, quarantined)
        found = self._scope_own.get(key)
        if found is None:
            own = tuple(c for c in self.scoped.get(goal_id, ()) if c.key not in quarantined)
            found = self._scope_own[key] = (own, tuple(self.constraint_item(c) for c in own))
        return found

    def fact_items(self, goal: Goal, needs: Reads, suffix: str = "") -> list[Item]:
        """The goal's facts that the expressions read: its behaviour, its area, and whether
        its area carries each tag they name."""
        items: list[Item] = []
        label = self.goal_label(goal)
        if needs.behavior:
            items.append(behavior_item(self, goal, label, suffix))
        if needs.area:
            items.append(area_item(self, goal, label, suffix))
        facts = self.facts(goal)
        for tag in sorted(needs.tags):
            items.append(context_item(self, goal, label, tag, tag in facts.tags, suffix))
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
        breach_key = f"breach:{n.key}"
        # Every goal the norm is relevant to asks: no closures for known items.
        known, known_breach = self._items.get(n.key), self._items.get(breach_key)
        if known is not None and known_breach is not None:
            return known, known_breach

        def build_rule() -> Item:
            permissions = self.permissions if n.modality == "forbidden" else []
            quantities = tuple(sorted(self.norm_reads(n).quantities))
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
                        expr_formula(self.breach_expr(n), negate=True), quantities=quantities,
                        meaning=("expr", ("norm", n.key, True), (self.breach_expr(n), True)))

        rule = self._memo(n.key, build_rule)
        broken = self._memo(breach_key, lambda: Item(
            breach_key, "breach", n.norm.id, lambda: rule.phrase, "breach|" + rule.source,
            expr_formula(self.breach_expr(n)), quantities=rule.quantities,
            meaning=("expr", ("norm", n.key, False), (self.breach_expr(n), False)),
        ))
        return rule, broken

    def norm_reads(self, n: ParsedNorm) -> Reads:
        if n.modality != "forbidden":
            return n.reads
        found = self._norm_reads.get(n.key)  # every goal the norm is relevant to asks
        if found is None:
            found = self._norm_reads[n.key] = _merge_reads(
                [n.reads, *(p.reads for p in self.permissions)])
        return found

    def scope_needs(self, goal_id: str, extra: tuple[Reads, ...]) -> Reads:
        """What the constraints in a goal's scope and the `extra` reads read together:
        thousands of goals share a few of these."""
        scope = self.scope_reads(goal_id)
        found = self._needs.get((scope, extra))
        if found is None:
            found = self._needs[scope, extra] = _merge_reads([scope, *extra])
        return found
