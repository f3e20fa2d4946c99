"""Status-only checks that one solver call serves for many units.

Most units of a large mission are fine: their items can hold together, and no breach or
failing state is possible. Such a unit's result holds no core and no witness, so only the
satisfiability of its items matters, and that depends on the set of their formulas alone, not
on which goal they belong to, their order or their indicator literals. The screen therefore:

- parses each distinct formula once per context (its z3 term is kept, never SMT text again),
- asserts a unit's formulas plainly in a push/pop scope (no indicators, no core to extract;
  a mission's hundreds of constraints share a few dozen distinct formulas),
- remembers the status of every formula set it decided, so goals with the same envelope,
  facts and constraints in scope (the same set of formulas) take one check between them.

A unit whose answer is not the plain one (a contradiction, a refusal, a risk, a failing state,
a timeout) is solved again by the session, one unit at a time with cores and witnesses, exactly
as without the screen: the screen only ever spares a check whose outcome it has proven.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from itertools import filterfalse
from typing import Any

from ...orders.model import Quantity
from ..expressions import Translator
from ..z3_adapter import Status, check_asserting
from .bounds import Decider
from .items import Item
from .limits import Limits
from .session import LazySolver


class Screen(LazySolver):
    """One z3 context and solver for status-only checks (one per logic model, like the
    session, so check_logic and check_properties on one version share parsed terms), made at
    the first check that bounds propagation leaves to z3."""

    def __init__(self, quantities: dict[str, Quantity], limits: Limits) -> None:
        self.limits = limits
        self.translator = Translator(quantities)
        # Units that bounds propagation settles take no z3 check at all.
        self.decider = Decider(quantities)
        self._timeout: int | None = None
        # Item -> formula text (an item's formula never changes within a model; items are
        # made once per model, so the object itself is the key, looked up at C speed).
        self._texts: dict[Item, str] = {}
        # Formula text -> its parsed term (the Python object holds z3's reference).
        self._terms: dict[str, Any] = {}
        # Decided (base, other) formula sets -> "sat" or "unsat" (undecided: asked again).
        self._decided: dict[tuple[frozenset[str], frozenset[str]], Status] = {}
        # The items asserted below every check, and their formulas (see `_rebase`).
        self._base: frozenset[Item] = frozenset()
        self._base_texts: frozenset[str] = frozenset()
        self.calls = 0
        self.shared = 0

    def _text(self, item: Item) -> str:
        text = self._texts[item] = item.formula(self.translator)
        return text

    def _texts_of(self, items: Iterable[Item]) -> frozenset[str]:
        texts = self._texts
        try:  # at C speed when every item was seen before (the usual case)
            return frozenset(map(texts.__getitem__, items))
        except KeyError:
            return frozenset(texts.get(i) or self._text(i) for i in items)

    def _parse(self, texts: Sequence[str]) -> None:
        """Parse new formulas in one call: declarations of every symbol so far, then one
        assertion per formula, read back as terms in the order given."""
        declarations = self.translator.declarations()
        parsed = self.z3.parse_smt2_string(
            declarations + "".join(f"(assert {t})" for t in texts), ctx=self.ctx)
        for text, term in zip(texts, parsed, strict=True):
            self._terms[text] = term

    def _rebase(self, base: frozenset[Item]) -> None:
        """Assert the mission-wide constraints once, below every check's scope: every unit of
        a run holds the same ones (its goal's scope always does), and z3 then takes them in
        once rather than at every check. Another set (another run's quarantine) starts a new
        solver."""
        self.solver = self.z3.SimpleSolver(ctx=self.ctx)
        self._timeout = None
        texts = self._texts_of(base)
        self._need(texts)
        for text in sorted(texts):
            self.solver.add(self._terms[text])
        self._base, self._base_texts = base, texts

    def _need(self, texts: Iterable[str]) -> None:
        fresh = [t for t in texts if t not in self._terms]
        if fresh:
            self._parse(sorted(fresh))

    def status(self, items: Sequence[Item], base: frozenset[Item] = frozenset()) -> Status:
        """Whether the items can hold together: "sat", "unsat" or "unknown" (a timeout or the
        run's budget spent). `base`: items that every check of the run holds (the live
        mission-wide constraints), asserted once below the checks' scope."""
        rest = list(filterfalse(base.__contains__, items)) if base else list(items)
        if len(items) - len(rest) != len(base):  # base not all among the items: no base
            rest, base = list(items), frozenset()
        decided = self.decider.status(rest, base)
        if decided is not None:
            return decided  # type: ignore[return-value]
        if base is not self._base and base != self._base:
            self._rebase(base)
        key = (self._base_texts, self._texts_of(rest))
        known = self._decided.get(key)
        if known is not None:
            self.shared += 1
            return known
        timeout = self.limits.call_timeout_ms()
        if timeout <= 0:
            return "unknown"
        if timeout != self._timeout:
            self.solver.set("timeout", timeout)
            self._timeout = timeout
        self._need(key[1])
        terms = self._terms
        self.calls += 1
        try:
            status = check_asserting(self.z3, self.ctx, self.solver,
                                     [terms[t].as_ast() for t in key[1]])
        except self.z3.Z3Exception:  # pragma: no cover - defensive: the session decides
            return "unknown"
        if status != "unknown":
            self._decided[key] = status
        return status
