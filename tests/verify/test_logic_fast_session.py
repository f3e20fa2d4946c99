"""The logic session's shortcuts (raw z3 ASTs kept per item, cores read through the C API,
formula text and goal items kept per session) give exactly the findings of the straightforward
session, and ask z3 exactly the same questions.

The reference below is the session as it was before them: a Python literal per assumption
asked for its AST at every check, cores read through z3's wrapper, every formula translated
again each time it is asserted. z3's answers depend on what it was asked
before (a witness or the core a shrink finds can change with the order of checks, and even
with the ids z3 gives new terms), so the shortcuts must not change which checks are made, in
which order: the checks themselves are compared as well as the findings."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any, ClassVar

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.logic import CheckResult, Item, LogicCache, Session, check_logic
from countersign.verify.logic import run as logic_run
from countersign.verify.properties import check_properties
from countersign.verify.z3_adapter import check_asts
from tests.bench.bench_logic import logic_orders


class ReferenceSession(Session):
    """The session without its shortcuts."""

    asked: ClassVar[list[tuple[str, ...]]] = []

    def _assert(self, items: Iterable[Item]) -> None:
        chunks: list[str] = []
        for item in items:
            name, new = self._indicator(item)
            self._items[name] = item
            if new:
                chunks.append(f"(declare-const |{name}| Bool)")
            chunks.append(f"(assert (=> |{name}| {item.formula(self.translator)}))")
        symbols = self.translator.symbols
        if len(symbols) > self._declared_symbols:
            fresh = list(symbols.items())[self._declared_symbols:]
            self._declared_symbols = len(symbols)
            chunks.insert(0, "".join(f"(declare-const {s} {sort})" for s, sort in fresh))
        if chunks:
            self.solver.from_string("".join(chunks))

    def _literal(self, item: Item) -> Any:
        literal = self.z3.Bool(self._indicators[item.key], self.ctx)
        self._ids[item.key] = literal.get_id()
        return literal

    def check(self, items: Sequence[Item]) -> CheckResult:
        self.asked.append(tuple(i.key for i in items))
        self.ready()  # a scope's items are asserted at its first check
        z3 = self.z3
        timeout = self.limits.call_timeout_ms()
        if timeout <= 0:
            self.undecided = True
            return CheckResult("unknown", reason="time budget exhausted")
        if timeout != self._timeout:
            self.solver.set("timeout", timeout)
            self._timeout = timeout
        self.calls += 1
        literals = [self._literal(i) for i in items]  # a Python expression per assumption
        status = check_asts(z3, self.ctx, self.solver, [literal.as_ast() for literal in literals])
        if status == "sat":
            return CheckResult("sat")
        if status == "unsat":
            ids = {literal.get_id() for literal in self.solver.unsat_core()}
            core = tuple(i for i in items if self._ids[i.key] in ids)
            return CheckResult("unsat", core or tuple(items))
        self.undecided = True
        return CheckResult("unknown", reason=self.solver.reason_unknown())


class CountingSession(Session):
    """The session as it is, recording the checks it is asked to make."""

    asked: ClassVar[list[tuple[str, ...]]] = []

    def check(self, items: Sequence[Item]) -> CheckResult:
        self.asked.append(tuple(i.key for i in items))
        return super().check(items)


def all_findings(orders: Orders, reference: bool) -> tuple[list[dict[str, Any]],
                                                            list[tuple[str, ...]]]:
    kind = ReferenceSession if reference else CountingSession
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(logic_run, "Session", kind)
        patch.setattr(kind, "asked", [])
        cache = LogicCache()
        # A generous budget: a run cut short by it reports different undecided warnings.
        found = check_logic(orders, cache, total_timeout_s=600)
        found += check_properties(orders, build_graph(orders), cache, total_timeout_s=600)
        session = cache.model(orders).session
        assert session is not None
        assert isinstance(session, ReferenceSession) is reference
        return [f.to_json() for f in found], kind.asked


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_fast_session_equals_the_reference(seed: int) -> None:
    orders = logic_orders(goals=60, constraints=30, norms=8, seed=seed)
    fast, fast_calls = all_findings(orders, reference=False)
    slow, slow_calls = all_findings(orders, reference=True)
    assert fast == slow
    assert fast_calls == slow_calls
    codes = {f["code"] for f in fast}
    assert {"NORM", "PROPERTY", "VACUOUS"} <= codes or seed != 1


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), goals=st.integers(3, 60), constraints=st.integers(2, 50),
       norms=st.integers(0, 8))
def test_fast_session_equals_the_reference_on_random_orders(
    seed: int, goals: int, constraints: int, norms: int
) -> None:
    orders = logic_orders(goals=goals, constraints=constraints, norms=norms, seed=seed)
    fast, fast_calls = all_findings(orders, reference=False)
    slow, slow_calls = all_findings(orders, reference=True)
    assert fast == slow
    assert fast_calls == slow_calls
