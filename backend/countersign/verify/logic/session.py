"""A z3 session: items asserted behind indicators, checks under a time budget."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property
from typing import Any, Literal

from ...orders.model import Quantity
from ..expressions import (
    Translator,
    number_words,
)
from ..z3_adapter import assert_any, bool_constant, check_asts, true_in_model, unsat_core_ids
from .items import Item
from .limits import BUDGET_SPENT, Limits


def _z3() -> Any:
    import z3

    return z3


class LazySolver:
    """z3, a context of its own and a solver in it, each made when first used: a run whose
    checks bounds propagation settles loads none of them."""

    @cached_property
    def z3(self) -> Any:
        return _z3()

    @cached_property
    def ctx(self) -> Any:
        return self.z3.Context()

    @cached_property
    def solver(self) -> Any:
        return self.z3.SimpleSolver(ctx=self.ctx)


@dataclass(frozen=True)
class CheckResult:
    status: Literal["sat", "unsat", "unknown"]
    core: tuple[Item, ...] = ()
    reason: str = ""


class Session(LazySolver):
    """A z3 context and an incremental solver. Shared items are asserted once at the base
    level; goal-specific items inside a push/pop scope. z3 itself is loaded and the context
    made at the first check: a run whose units bounds propagation settles makes none."""

    def __init__(self, quantities: dict[str, Quantity], limits: Limits) -> None:
        self.limits = limits
        self.translator = Translator(quantities)
        self._timeout: int | None = None
        self._declared_symbols = 0
        self._indicators: dict[str, str] = {}
        self._ids: dict[str, int] = {}
        # Per item key: the indicator's raw AST, and the formula's SMT text (the same item
        # is asserted again for every unit that reads it; its text never changes).
        self._asts: dict[str, Any] = {}
        self._formulas: dict[str, str] = {}
        self._based: set[str] = set()
        # Where the current unit's witnesses are solved (see `witness`); a new one per unit.
        self._unit_context: Any = None
        self._items: dict[str, Item] = {}
        self.in_scope = False
        self._pending: Iterable[Item] | None = None
        self._pushed = False
        self._batches = 0
        # Calls that bounds propagation answered (`owe_check`, `owe_groups`), made in z3 all
        # the same before its next call: which of several cores z3 names depends on what the
        # solver took in before, and must not depend on which answers bounds gave.
        self._owed: list[Callable[[], object]] = []
        self.calls = 0
        self.undecided = False
        # Proves some item sets satisfiable without z3 (bounds.py, set by the run); a core's
        # shrinking asks it first. Only "sat" is taken from it: an unsatisfiable subset's
        # core still comes from z3, so the shrinking takes the steps it takes without it.
        self.proven: Callable[[Sequence[Item]], bool] | None = None

    def _indicator(self, item: Item) -> tuple[str, bool]:
        name = self._indicators.get(item.key)
        if name is not None:
            return name, False
        name = f"a:{len(self._indicators)}"
        self._indicators[item.key] = name
        return name, True

    def _formula(self, item: Item) -> str:
        """The item's formula as SMT text, made once per key."""
        formula = self._formulas.get(item.key)
        if formula is None:
            formula = self._formulas[item.key] = item.formula(self.translator)
        return formula

    def _assert(self, items: Iterable[Item]) -> None:
        chunks: list[str] = []
        for item in items:
            name, new = self._indicator(item)
            self._items[name] = item
            formula = self._formula(item)
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
        """Make items checkable: shared ones permanently, the others until the scope ends.
        They are asserted at the scope's first check: a unit whose answers all came without
        z3 (bounds.py, unique.py) asserts nothing."""
        assert not self.in_scope
        self._pending = items
        self.in_scope = True
        try:
            yield
        finally:
            if self._pushed:
                self.solver.pop()
            self._pushed = False
            self._pending = None
            self.in_scope = False
            self._unit_context = None

    def _enter(self, items: Iterable[Item]) -> None:
        self._pending = None
        items = list(items)
        shared = [i for i in items if i.shared and i.key not in self._based]
        if shared:
            self._assert(shared)
            self._based.update(i.key for i in shared)
        self.solver.push()
        self._pushed = True
        self._assert(i for i in items if not i.shared)

    def _ast(self, item: Item) -> Any:
        found = self._asts.get(item.key)
        if found is None:
            found, self._ids[item.key] = bool_constant(
                self.z3, self.ctx, self._indicators[item.key])
            self._asts[item.key] = found
        return found

    def ready(self) -> None:
        """Assert what the current scope holds, if not yet done (before any z3 check)."""
        if self._pending is not None:
            self._enter(self._pending)

    @property
    def entered(self) -> bool:
        """Whether the current scope's items are asserted (a check ran in it)."""
        return self._pushed

    def owe_check(self, items: Sequence[Item]) -> None:
        """A check in a scope of its own (or the first of the current scope), proven
        satisfiable without z3: z3 makes it before its next call, in a scope of its own."""
        assert not self._pushed
        self._owed.append(lambda: self._replay_check(list(items)))

    def owe_groups(self, groups: Sequence[Sequence[Item]]) -> None:
        """A `satisfiable_groups` call whose every group was proven satisfiable without z3."""
        self._owed.append(lambda: self._groups([list(g) for g in groups]))

    def _settle(self) -> None:
        owed, self._owed = self._owed, []
        undecided = self.undecided
        for call in owed:
            call()
        self.undecided = undecided

    def _replay_check(self, items: list[Item]) -> None:
        pending = self._pending  # the scope now open: entered at its own first check
        self._enter(items)
        self._check(items)
        self.solver.pop()
        self._pending, self._pushed = pending, False

    def check(self, items: Sequence[Item]) -> CheckResult:
        if self._owed:
            self._settle()
        self.ready()
        return self._check(items)

    def _check(self, items: Sequence[Item]) -> CheckResult:
        z3 = self.z3
        timeout = self.limits.call_timeout_ms()
        if timeout <= 0:
            self.undecided = True
            return CheckResult("unknown", reason=self.limits.spent() or BUDGET_SPENT)
        if timeout != self._timeout:
            self.solver.set("timeout", timeout)
            self._timeout = timeout
        self.calls += 1
        asts = self._asts
        try:
            literals = [asts[i.key] for i in items]
        except KeyError:  # the first check of some item: make its literal
            literals = [asts.get(i.key) or self._ast(i) for i in items]
        # The C call directly (z3_adapter): the wrapper's own checks cost more than solving.
        try:
            status = check_asts(z3, self.ctx, self.solver, literals)
        except z3.Z3Exception as exc:  # pragma: no cover - defensive: never crash a report
            self.undecided = True
            return CheckResult("unknown", reason=f"solver error: {exc}")
        if status == "sat":
            return CheckResult("sat")
        if status == "unsat":
            ids = unsat_core_ids(z3, self.ctx, self.solver)
            known = self._ids
            core = tuple(i for i in items if known[i.key] in ids)
            return CheckResult("unsat", core or tuple(items))
        self.undecided = True
        reason = self.solver.reason_unknown()
        if reason in {"canceled", "timeout"}:
            # A call the limits cut short says so: the goal may be easy, the time was gone.
            reason = self.limits.timed_out()
        return CheckResult("unknown", reason=reason)

    def satisfiable_groups(self, groups: Sequence[Sequence[Item]]) -> list[bool]:
        """Which groups of items are shown satisfiable (each on its own), with few checks:
        ask for a model of "some group holds", mark every group that model satisfies, and
        ask again for the rest. False means not shown (unsatisfiable or undecided): the caller
        checks those one by one, so results are those of one check per group."""
        assert not self.in_scope
        if self._owed:
            self._settle()
        return self._groups(groups)

    def _groups(self, groups: Sequence[Sequence[Item]]) -> list[bool]:
        shown = [False] * len(groups)
        if not groups or self.limits.call_timeout_ms() <= 0:
            return shown
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
                timeout = self.limits.call_timeout_ms()
                if timeout <= 0:
                    break
                if timeout != self._timeout:
                    self.solver.set("timeout", timeout)
                    self._timeout = timeout
                self.calls += 1
                self.solver.push()
                try:
                    candidates = [literals[i] for i in pending]
                    assert_any(z3, self.ctx, self.solver, candidates)
                    if self.solver.check() != z3.sat:
                        break
                    model = self.solver.model()
                    found = [i for i, true in zip(pending, true_in_model(
                        z3, self.ctx, model, candidates), strict=True) if true]
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

    def witness(self, quantities: Iterable[str], suffix: str = "",
                items: Sequence[Item] = ()) -> dict[str, str]:
        """Values of some quantities in a model of `items` (those of the last satisfiable
        check), or of the last check itself when no items are given or no model of them is
        found in time.

        z3's model depends on the ids its context gave terms before (it orders a disjunction's
        operands by id), so a model from the shared session changes with what the session
        checked earlier: re-validating, where the cache spares some units, would name other
        values. The items are solved again in a context of the current unit's own, which has
        seen only this unit's witnesses: the same items give the same values."""
        z3 = self.z3
        found = self._model_of(items) if items else None
        model, ctx = found if found is not None else (self.solver.model(), self.ctx)
        translator = self.translator.with_suffix(suffix)
        values: dict[str, str] = {}
        for name in quantities:
            symbol, kind = translator.quantity(name)
            sort = {"boolean": z3.BoolSort(ctx), "integer": z3.IntSort(ctx)}.get(
                kind, z3.RealSort(ctx)
            )
            value = model.eval(z3.Const(symbol.strip("|"), sort), model_completion=True)
            if kind == "boolean":
                values[name] = "true" if z3.is_true(value) else "false"
            elif kind == "integer":
                values[name] = str(value.as_long())
            else:
                values[name] = _decimal(value)
        return values

    def _model_of(self, items: Sequence[Item]) -> tuple[Any, Any] | None:
        """(a model of the items alone, its context), or None when not found in time."""
        timeout = self.limits.call_timeout_ms()
        if timeout <= 0:
            return None
        formulas = list(dict.fromkeys(self._formula(i) for i in items))
        text = "".join(formulas)
        # Only the symbols these formulas use, in a fixed order: each declaration makes a
        # term, and what the context made before moves the ids of what follows.
        declarations = "".join(f"(declare-const {symbol} {sort})"
                               for symbol, sort in sorted(self.translator.symbols.items())
                               if symbol in text)
        if self._unit_context is None:
            self._unit_context = self.z3.Context()
        ctx = self._unit_context
        solver = self.z3.SimpleSolver(ctx=ctx)
        solver.set("timeout", timeout)
        solver.from_string(declarations + "".join(f"(assert {f})" for f in formulas))
        self.calls += 1
        return (solver.model(), ctx) if solver.check() == self.z3.sat else None

    def earliest_twins(self, core: Sequence[Item], items: Sequence[Item]) -> list[Item]:
        """The core with each item replaced by the first of `items` of its kind that states
        the same formula. Which of two identical constraints z3 names depends on what the session
        solved before (its term ids and learned clauses), so without this a core could name
        C184 in one run and its twin C52 in another; the first in the orders is named always.
        A twin states the same thing, so the core stays unsatisfiable and minimal."""
        def twin(item: Item) -> tuple[str, str]:
            # Of the same kind too: a domain and a vehicle bound may read alike, not the same.
            return item.kind, self._formula(item)

        wanted = {twin(i) for i in core}
        first: dict[tuple[str, str], Item] = {}
        for item in items:
            key = twin(item)
            if key in wanted:
                first.setdefault(key, item)
        return [first.get(twin(i), i) for i in core]

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
        result = self._shrink_check([*s0, *first])
        if result.status == "unsat":
            inside = [i for i in first if i in result.core]
            return self._minimise(inside, s0) if inside else []
        result = self._shrink_check([*s0, *second])
        if result.status == "unsat":
            inside = [i for i in second if i in result.core]
            return self._minimise(inside, s0) if inside else []
        first_min = self._minimise(first, [*s0, *second])
        second_min = self._minimise(second, [*s0, *first_min])
        return first_min + second_min

    def _shrink_check(self, items: list[Item]) -> CheckResult:
        if self.proven is not None and self.proven(items):
            return CheckResult("sat")
        return self.check(items)


def _decimal(value: Any) -> str:
    try:
        fraction = Fraction(value.numerator_as_long(), value.denominator_as_long())
    except Exception:  # algebraic numbers from nonlinear problems
        return str(value.as_decimal(6)).rstrip("?")
    return number_words(fraction)
