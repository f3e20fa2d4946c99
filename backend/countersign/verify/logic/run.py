"""One run of the logic check: the units, their cache and their solver session."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from itertools import filterfalse
from typing import Any

from ...orders.model import Goal
from ..expressions import (
    Reads,
)
from .cache import LogicCache, unit_key, unit_key_apart
from .constants import _KIND_ORDER, MAX_CORES_PER_UNIT
from .items import Item, Part
from .limits import Limits
from .model import GoalItems, LogicModel, ParsedConstraint
from .results import Core, GoalResult, MissionResult, Risk, VacuousResult
from .screen import Screen
from .session import CheckResult, Session
from .unique import UniqueCores

# Units whose plain outcome (no core, no witness) the screen proves take no session check, and
# goals with the same formulas share one screen check (False: every unit solved one by one in
# the session, the reference the screened path is tested against).
GROUP_CHECKS = True


class LogicRun:
    """One run of checks: the units, the cache and the model's z3 session."""

    def __init__(self, model: LogicModel, cache: LogicCache | None, limits: Limits) -> None:
        self.model = model
        self.cache = cache if cache is not None else LogicCache()
        self.limits = limits
        self._session: Session | None = None
        self._blocks: dict[frozenset[str], frozenset[Item]] = {}
        self._norms: dict[tuple[str | None, str | None], tuple[
            list[Reads], list[tuple[Item, Item]], list[tuple[Item, Item]], list[Item]]] = {}

    @property
    def session(self) -> Session:
        """The model's z3 session (one per version of the orders), under this run's limits.
        Callers hold `model.lock` for the whole run."""
        if self._session is None:
            session = self.model.session
            if session is None:
                session = self.model.session = Session(self.model.quantities, self.limits)
            session.limits = self.limits
            session.proven = self._proven if GROUP_CHECKS else None
            self._session = session
        return self._session

    @property
    def unique_cores(self) -> UniqueCores:
        found = self.model.unique_cores
        if found is None:
            order = {c.key: n for n, c in enumerate(self.model.mission_constraints)}
            found = self.model.unique_cores = UniqueCores(self.screen.decider, order)
        return found

    def _proven(self, items: Sequence[Item]) -> bool:
        return self.screen.decider.status(items, frozenset()) == "sat"

    @property
    def screen(self) -> Screen:
        """The model's status-only checks (screen.py), under this run's limits."""
        screen = self.model.screen
        if screen is None:
            screen = self.model.screen = Screen(self.model.quantities, self.limits)
        screen.limits = self.limits
        return screen

    def block(self, quarantined: frozenset[str]) -> frozenset[Item]:
        """The live mission-wide constraints' items, which the screen asserts once."""
        found = self._blocks.get(quarantined)
        if found is None:
            found = self._blocks[quarantined] = self.model.mission_block(quarantined)
        return found

    def screened(self, items: Sequence[Item], base: frozenset[Item]) -> CheckResult:
        """Whether `items` can hold, no core read: the screen's answer when it decides (goals
        with the same formulas share it), else the session's."""
        if GROUP_CHECKS:
            status = self.screen.status(items, base)
            if status in ("sat", "unsat"):
                return CheckResult(status)
        return self.session.check(items)

    def cached(self, kind: str, items: Iterable[Item], solve: Callable[[], Any],
               base: frozenset[Item] | None = None, apart: Sequence[Item] | None = None
               ) -> Any:
        """The unit's result from the cache, or solved and put there. `apart`: the items but
        the base, when the caller holds them apart (and every item of the base is among
        `items`)."""
        return self.keyed(kind, items, solve, base, apart)[1]

    def keyed(self, kind: str, items: Iterable[Item], solve: Callable[[], Any],
              base: frozenset[Item] | None = None, apart: Sequence[Item] | None = None
              ) -> tuple[str, Any]:
        """`cached`, with the unit's key: a caller that carries the result to the next run
        checks with `cache.holds` that the key still gives it."""
        if base is None:  # a goal's unit (of a property too) holds the run's live block
            base = next(iter(self._blocks.values())) if len(self._blocks) == 1 else frozenset()
        key = unit_key(kind, items, base) if apart is None else unit_key_apart(kind, apart, base)
        found = self.cache.get(key)
        if found is not None:
            return key, found
        result = solve()
        # What a timeout cut short (undecided, or a core not proven minimal) is tried again.
        cores = [c for name in ("cores", "contradictions", "refusals", "core")
                 for c in _as_tuple(getattr(result, name, ()))]
        if getattr(result, "undecided", None) is None and all(c.minimal for c in cores):
            self.cache.put(key, result)
        return key, result

    def cores(self, items: list[Item], drop: Callable[[list[Item]], list[Item]],
              limit: int = MAX_CORES_PER_UNIT, base: frozenset[Item] | None = None
              ) -> tuple[list[Core], list[Item], str | None]:
        """Minimal cores of an item set, dropping items after each so that independent
        contradictions are all found (up to a limit). Returns (cores, remaining, undecided).
        With `base` (a goal's unit), whether the items (what is left) can hold is asked of the
        screen first: often they can, and then no session check is needed."""
        session = self.session
        screen = GROUP_CHECKS and base is not None

        def check(items: list[Item]) -> CheckResult:
            # A scope's first check that bounds propagation proves satisfiable waits for z3's
            # next call (if any: a mission whose every unit bounds settle never loads z3).
            if GROUP_CHECKS and not session.entered and self._proven(items):
                session.owe_check(items)
                return CheckResult("sat")
            return session.check(items)

        def first(items: list[Item]) -> tuple[CheckResult, list[Item] | None]:
            """The check's result, and the unit's only core when bounds.py proves there is
            one (unique.py: z3 and the shrinking would end at it too). With a base the
            screen answers first, once for both questions."""
            if not screen:
                return check(items), None
            assert base is not None
            status = self.screen.status(items, base)
            if status == "sat":
                return CheckResult("sat"), None
            known = self.unique_cores.core(items, base) if status == "unsat" else None
            return ((CheckResult("unsat"), known) if known is not None
                    else (session.check(items), None))

        found: list[Core] = []
        first_items = items
        result, known = first(items)
        while result.status == "unsat" and len(found) < limit:
            if known is not None:
                core, minimal = known, True
            else:
                core, minimal = session.minimal_core(result.core)
                if not core:
                    break
                core = session.earliest_twins(core, items)
            found.append(Core(tuple(sorted_parts(core)), minimal))
            removed = drop(core)
            if not removed:
                break
            items = list(filterfalse(set(removed).__contains__, items))
            result, known = first(items)
        undecided = result.reason if result.status == "unknown" else None
        # Which of several independent cores z3 names first depends on what the session solved
        # before; listed by where their items stand in the unit, they read the same whatever
        # was solved before (and whether the screen spared some checks).
        if len(found) > 1:
            place = {item.key: n for n, item in enumerate(first_items)}
            found.sort(key=lambda c: sorted(place.get(p.key, len(place)) for p in c.parts))
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
        found = self._goal_parts(goal, quarantined, extra)
        return self._all_items(found, quarantined), [*self.model.live_block(quarantined)[0],
                                                     *found.own_constraints]

    def _all_items(self, parts: GoalItems, quarantined: frozenset[str]) -> list[Item]:
        """A goal's items with the mission-wide block, in the order a unit checks them."""
        return [*parts.head, *self.model.live_block(quarantined)[1], *parts.own, *parts.tail]

    def _goal_parts(self, goal: Goal, quarantined: frozenset[str],
                    extra: Sequence[Reads]) -> GoalItems:
        model = self.model
        # Once per goal and model; a model made after a one-goal edit starts with the other
        # goals' lists of the model before it (LogicModel.carry_goal_items).
        memo = (goal.id, quarantined, tuple(extra))
        found = model.goal_items_memo.get(memo)
        if found is None:
            own_constraints, own = model.scope_own(goal.id, quarantined)
            needs = model.scope_needs(goal.id, memo[2])
            names = set(goal.envelope) | needs.quantities
            head = [model.envelope_item(goal, name) for name in sorted(goal.envelope)]
            head += model.fact_items(goal, needs)
            background = model.background(names)
            tail = ([i for i in background if i.key not in quarantined] if quarantined
                    else background)
            found = model.goal_items_memo[memo] = GoalItems(
                tuple(head), own, tuple(tail), own_constraints)
        return found

    def goal(self, goal: Goal, quarantined: frozenset[str]) -> GoalResult:
        result: GoalResult = self.goal_keyed(goal, quarantined)[1]
        return result

    def goal_keyed(self, goal: Goal, quarantined: frozenset[str]) -> tuple[str, GoalResult]:
        """The goal's unit key and result."""
        extra, norm_items, residual, added = self._goal_norms(goal)
        parts = self._goal_parts(goal, quarantined, extra)
        # The goal's items but the block, listed apart once: no check scans the block's
        # hundreds of items to find them again.
        own = [*parts.head, *parts.own, *parts.tail]
        base = self.block(quarantined)
        return self.keyed(  # the key reads `apart` (and the base) only: no list of them all
            "goal", (), lambda: self._solve_goal(self._all_items(parts, quarantined), own,
                                                 norm_items, residual, base),
            base, apart=own + added)

    def _goal_norms(self, goal: Goal) -> tuple[
        list[Reads], list[tuple[Item, Item]], list[tuple[Item, Item]], list[Item]
    ]:
        """What a goal's relevant norms read, their (rule, breach) items, those whose breach
        depends on quantities, and their items in one list: the goal's behaviour and area
        decide them all, so thousands of goals share a few dozen (lists not to be changed)."""
        key = (goal.behavior, goal.area)
        found = self._norms.get(key)
        if found is None:
            model = self.model
            norms = model.relevant_norms(goal)
            pairs = [model.norm_items(n) for n in norms]
            found = self._norms[key] = (
                [model.norm_reads(n) for n in norms], pairs,
                [pair for n, pair in zip(norms, pairs, strict=True) if model.residual(n, goal)],
                [i for pair in pairs for i in pair])
        return found

    def _solve_goal(self, items: list[Item], own: list[Item],
                    norm_items: list[tuple[Item, Item]], residual: list[tuple[Item, Item]],
                    base: frozenset[Item]) -> GoalResult:
        if GROUP_CHECKS and self._plain_goal(items, own, [rule for rule, _ in norm_items],
                                             residual, base):
            return GoalResult((), (), (), None)
        return self._solve_goal_alone(items, norm_items, residual, base)

    def _plain_goal(self, items: list[Item], own: list[Item], rules: list[Item],
                    residual: list[tuple[Item, Item]], base: frozenset[Item]) -> bool:
        """Whether the screen proves the goal's result holds nothing: its items and norms can
        hold together (no contradiction, no refusal) and no residual norm can be breached (no
        risk). That is the answer `_solve_goal_alone` gives for exactly these statuses.
        `own`: the items but the base."""
        screen = self.screen
        decide = screen.decider.status

        def status(extra: list[Item]) -> str:
            return decide(own + extra, base) or screen.status(items + extra, base)

        if status(rules) != "sat":
            return False
        return all(status([breach]) == "unsat" for _, breach in residual)

    def _solve_goal_alone(self, items: list[Item], norm_items: list[tuple[Item, Item]],
                          residual: list[tuple[Item, Item]],
                          base: frozenset[Item] | None = None) -> GoalResult:
        """The goal's result, one check at a time in the session, cores and witnesses from
        it. With `base` the checks whose status alone is read go to the screen first."""
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
            together = (None if not rules
                        else self.screened(items + rules, base) if base is not None
                        else session.check(items + rules))
            if together is None or together.status != "sat":
                contradictions, _, undecided = self.cores(items, drop_contradiction, base=base)
                if contradictions or undecided is not None or not rules:
                    return GoalResult(tuple(contradictions), (), (), undecided)
                refusals, _, undecided = self.cores(items + rules, drop_norms,
                                                    limit=len(rules), base=base)
            refused = {i.key for core in refusals for i in core.parts}
            risks: list[Risk] = []
            for rule, breach in residual:
                if rule.key in refused or undecided is not None:
                    continue
                # A breach the screen rules out needs no session check; one it allows does,
                # for the witness's fallback reads the session's last model.
                if GROUP_CHECKS and base is not None and self.screen.status(
                        [*items, breach], base) == "unsat":
                    continue
                result = session.check([*items, breach])
                if result.status == "sat":
                    witness = session.witness(breach.quantities, items=[*items, breach])
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
        groups = [items for _, items in pending]
        if groups and GROUP_CHECKS and all(self._proven(items) for items in groups):
            # z3 makes the call (of one group: `vacuous`'s check) before its next one, if any.
            if len(groups) == 1:
                self.session.owe_check(groups[0])
            else:
                self.session.owe_groups(groups)
            shown = [True] * len(groups)
        elif len(pending) < 2:
            return
        else:
            shown = self.session.satisfiable_groups(groups)
        for (key, _), sat in zip(pending, shown, strict=True):
            if sat:
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
