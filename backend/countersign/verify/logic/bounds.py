"""Satisfiability by bounds propagation, without z3, for the units it can settle.

Most statements of a mission are bounds on one quantity (envelopes, the vehicle, domains,
"depth_m >= 5") or become so once the goal's facts (behaviour, area, its tags) are put in
("behavior == 'sample' implies depth_m >= 8"). A unit of such statements is decided by
intersecting intervals; the few others (a disjunction, a sum of two quantities) are settled
over the resulting box: true on all of it, false on all of it, true at one of its points, or
split into their disjuncts. Each answer is a proof: "sat" names a box (or a point) where every
statement holds, "unsat" an empty box or a statement false on all of the box. Whatever this
cannot prove (a product of quantities, a division by a quantity, too many splits) is None, and
z3 decides as before: this only ever spares a check whose answer it has proven.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from fractions import Fraction
from itertools import filterfalse
from operator import attrgetter
from typing import Any, Literal

from ...orders.model import Quantity
from .formulas import (
    Facts,
    Formula,
    Number,
    Translate,
    Unsupported,
    compare_constant,
    exact,
    join,
)
from .items import Item, _bound

# Splits of disjunctions tried per check before leaving it to z3.
MAX_SPLITS = 64

# Formulas (formulas.py): True, False, linear comparisons, Booleans, texts, "&" and "|".
FactsKey = frozenset[tuple[Any, Any]]
# name -> (low, low strict, high, high strict); None: unbounded
Bounds = dict[str, tuple[Any, ...]]
Bools = dict[Any, Any]
# Booleans: a Boolean quantity or ("ctx", tag) -> its value, ("str", name) ->
# the text a behaviour or area with no fact is set to.


class Decider:
    """Decides units from their items' meanings (`Item.meaning`); one per logic model."""

    def __init__(self, quantities: Mapping[str, Quantity]) -> None:
        self.kinds = {name: q.type for name, q in quantities.items()}
        # (base, facts) -> the base's statements under those facts, propagated once.
        self._bases: dict[tuple[frozenset[int], FactsKey], Any] = {}
        # id(base) -> (the base, held so that its id is never another's; what its items state,
        # as `_codes_of` numbers, or None when some item is z3's only).
        self._base_codes: dict[int, tuple[frozenset[Item], frozenset[int] | None]] = {}
        self._formulas: dict[tuple[Any, FactsKey], Formula] = {}
        self._states: dict[tuple[Any, ...], Any] = {}
        self._starts: dict[tuple[Any, ...], Any] = {}
        self._translators: dict[FactsKey, Translate] = {}
        # Item -> the number of what it states (`_codes_of`); None: z3 only.
        self._item_codes: dict[Item, int | None] = {}
        self._said_codes: dict[Any, int] = {}
        self._verdicts: dict[tuple[Any, ...], str] = {}
        self._intervals: dict[Item | tuple[Any, ...], Any] = {}
        self.decided = 0
        self.propagated = 0  # units whose own statements were propagated (not remembered)

    def status(self, rest: Iterable[Item], base: frozenset[Item]) -> str | None:
        """"sat" or "unsat" when proven for `rest` and `base` together, else None."""
        if not base:  # one empty base for all: `frozenset()` makes a new object (a new id)
            base = _NO_BASE
        rest = rest if isinstance(rest, list) else list(rest)
        codes = self._codes_of(rest)
        if not any(map(_EXTRA, rest)):  # no norm nor breach (most checks of a unit's own items)
            own, extra = rest, []
            own_keys, extra_keys = frozenset(codes), _NO_EXTRA
            if None in own_keys:  # a hashed look-up, not a scan
                return None
        elif None in codes:
            return None
        else:
            own, extra = list(filterfalse(_EXTRA, rest)), list(filter(_EXTRA, rest))
            # The codes made above, split as the items are (not looked up again).
            own_keys = frozenset(c for i, c in zip(rest, codes, strict=True) if not _EXTRA(i))
            extra_keys = frozenset(c for i, c in zip(rest, codes, strict=True) if _EXTRA(i))
        # By what the base states, not by the set itself: a base without its twins (unique.py)
        # asks the questions its goal asked already.
        base_codes = self._codes_of_base(base)
        if base_codes is None:
            return None
        asked = (base_codes, own_keys, extra_keys)
        known = self._verdicts.get(asked)
        if known is not None:
            self.decided += 1
            return known
        if len(self._verdicts) > 200_000:
            self._verdicts.clear()
        try:
            # A goal's checks differ in their norms only: its own statements are propagated
            # once and the state reused for each norm or breach.
            memo = asked[:2]
            state = self._states.get(memo, _MISSING)
            if state is _MISSING:
                if len(self._states) > 64:
                    self._states.clear()
                state = self._states[memo] = self._state(own, base)
                self.propagated += 1
            if state is None:
                verdict: bool | None = False
            else:
                facts, key, bounds, bools, settled = state
                if extra:
                    formulas = [self._formula(i, facts, key) for i in extra]
                    verdict = _solve(formulas, dict(bounds), dict(bools), self.kinds,
                                     [MAX_SPLITS], settled)
                else:  # nothing to propagate: the state's box is read, never changed
                    verdict = _solve([], bounds, bools, self.kinds, [MAX_SPLITS], settled)
        except Unsupported:
            return None
        if verdict is None:
            return None
        found = self._verdicts[asked] = "sat" if verdict else "unsat"
        self.decided += 1
        return found

    def _codes_of(self, items: list[Item]) -> list[int | None]:
        """What each item states (`Item.said`) as a small number: goals' questions are keyed
        by sets of them, and a number hashes and compares at once where a statement's tuple
        is hashed again at every question."""
        try:  # at C speed when every item was seen before (the usual case)
            return list(map(self._item_codes.__getitem__, items))
        except KeyError:
            return [self._code(i) for i in items]

    def _codes_of_base(self, base: frozenset[Item]) -> frozenset[int] | None:
        found = self._base_codes.get(id(base))
        if found is None or found[0] is not base:
            codes = self._codes_of(list(base))
            found = self._base_codes[id(base)] = (
                base, None if None in codes else frozenset(codes))  # type: ignore[arg-type]
        return found[1]

    def _code(self, item: Item) -> int | None:
        found = self._item_codes.get(item, _MISSING)
        if found is _MISSING:
            said = item.said
            found = None if said is None else self._said_codes.setdefault(
                said, len(self._said_codes))
            self._item_codes[item] = found
        return found  # type: ignore[return-value]

    def _state(self, own: list[Item], base: frozenset[Item]) -> Any:
        """(facts, their key, bounds, Booleans, formulas left) of a unit's own statements and
        the base, propagated; None when they cannot hold (Unsupported: not decided here)."""
        facts: Facts = {}
        boxes: list[Item] = []
        shared: list[Item] = []
        exprs: list[Item] = []
        for item in own:
            meaning = item.meaning
            assert meaning is not None
            kind = meaning[0]
            if kind == "box":
                (shared if item.kind in _BACKGROUND else boxes).append(item)
            elif kind == "expr":
                exprs.append(item)
            elif kind != "fact":
                raise Unsupported
            elif facts.setdefault(meaning[1], meaning[2]) != meaning[2]:
                return None  # one fact with two values
        key = frozenset(facts.items())
        start = self._start(base, facts, key, frozenset(shared))
        if start is None:
            return None
        bounds = dict(start[0])
        bools = dict(start[1])
        for item in boxes:
            if not self._box(bounds, bools, item):
                return None
        formulas = [*start[2], *(self._formula(item, facts, key) for item in exprs)]
        rest = _propagate(formulas, bounds, bools, self.kinds)
        if rest is False:
            return None
        return facts, key, bounds, bools, rest

    def _start(self, base: frozenset[Item], facts: Facts, key: FactsKey,
               shared: frozenset[Item]) -> Any:
        """The base under the facts with the vehicle and domain intervals of a unit applied
        (not propagated further): thousands of goals read the same few sets of them, so each
        set is applied once, not once per goal. Intervals intersect in any order, and the
        formulas are propagated after every interval as before."""
        memo = (self._codes_of_base(base), key, shared)
        found = self._starts.get(memo, _MISSING)
        if found is _MISSING:
            found = start = self._base(base, facts, key)
            if start is not None:
                bounds = dict(start[0])
                bools = dict(start[1])
                ok = all(self._box(bounds, bools, item) for item in shared)
                found = (bounds, bools, start[2]) if ok else None
            if len(self._starts) > 4096:
                self._starts.clear()
            self._starts[memo] = found
        return found

    def false_by_facts(self, items: Sequence[Item]) -> Item | None:
        """The first statement among the items that their facts alone make false."""
        facts: Facts = {}
        for item in items:
            meaning = item.meaning
            if (meaning is not None and meaning[0] == "fact"
                    and facts.setdefault(meaning[1], meaning[2]) != meaning[2]):
                return None
        key = frozenset(facts.items())
        for item in items:
            if item.meaning is not None and item.meaning[0] == "expr":
                try:
                    if self._formula(item, facts, key) is False:
                        return item
                except Unsupported:
                    continue
        return None

    def _formula(self, item: Item, facts: Facts, key: FactsKey) -> Formula:
        assert item.meaning is not None
        memo = (item.meaning[1], key)
        found = self._formulas.get(memo)
        if found is None:
            expr, negate = item.meaning[2]
            translate = self._translators.get(key)
            if translate is None:  # one per set of facts: each holds its visitors in a cycle
                translate = self._translators[key] = Translate(self.kinds, dict(facts))
            found = self._formulas[memo] = translate.condition(expr, not negate)
        return found

    def _base(self, base: frozenset[Item], facts: Facts, key: FactsKey) -> Any:
        """(bounds, Booleans, other formulas) of the base under the facts, or None when the
        base alone cannot hold; Unsupported when it cannot be decided here."""
        codes = self._codes_of_base(base)
        assert codes is not None
        memo = (codes, key)
        found = self._bases.get(memo, _MISSING)
        if found is _MISSING:
            try:
                found = self._propagate_base(base, facts, key)
            except Unsupported:
                found = Unsupported
            self._bases[memo] = found
        if found is Unsupported:
            raise Unsupported
        return found

    def _propagate_base(self, base: frozenset[Item], facts: Facts, key: FactsKey) -> Any:
        bounds: Bounds = {}
        bools: Bools = {}
        formulas: list[Formula] = []
        seen: set[Any] = set()
        for item in sorted(base, key=lambda i: i.key):
            meaning = item.meaning
            if meaning is None or meaning[0] not in {"box", "expr"}:
                raise Unsupported
            if meaning[0] == "box":
                if not self._box(bounds, bools, item):
                    return None
            elif meaning[1] not in seen:
                seen.add(meaning[1])
                formulas.append(self._formula(item, facts, key))
        rest = _propagate(formulas, bounds, bools, self.kinds)
        if rest is False:
            return None
        return bounds, bools, rest

    def _box(self, bounds: Bounds, bools: Bools, item: Item) -> bool:
        """Add an envelope, vehicle or domain interval (as items.py states it to z3)."""
        assert item.meaning is not None
        found = self._intervals.get(item)  # by the item itself: hashed at C speed
        if found is None:  # by what it states: goals with the same envelope share it
            found = self._intervals.get(item.meaning)
            if found is None:
                found = self._intervals[item.meaning] = self._interval(*item.meaning[1:])
            self._intervals[item] = found
        name, kind, lo, hi, value = found
        if kind == "boolean":
            return value is None or _set_bool(bools, name, value)
        return (lo is None or _tighten(bounds, name, kind, lo, False, True)) and (
            hi is None or _tighten(bounds, name, kind, hi, False, False))

    def _interval(self, name: str, low: Any, high: Any) -> tuple[Any, ...]:
        """(name, kind, low, high, Boolean value) of an interval item, exact."""
        lo: Any = _bound(low) if low is not None else None
        hi: Any = _bound(high) if high is not None else None
        kind = self.kinds.get(name)
        if kind == "boolean":
            value: Any = None
            if lo is not None and lo > 0:
                value = True
            if hi is not None and hi < 1:
                value = False if value is None else _CONFLICT
            return name, kind, None, None, value
        if kind == "integer":
            lo = math.ceil(lo) if lo is not None else None
            hi = math.floor(hi) if hi is not None else None
        return name, kind, exact(lo), exact(hi), None


_MISSING = object()
_BACKGROUND = frozenset({"vehicle", "domain"})
_EXTRA = attrgetter("extra")
_NO_BASE: frozenset[Item] = frozenset()
_NO_EXTRA: frozenset[Any] = frozenset()
_UNBOUNDED = (None, False, None, False)
_CONFLICT = object()  # a Boolean interval that admits neither value


def _set_bool(bools: Bools, name: str, value: Any) -> bool:
    return value is not _CONFLICT and bools.setdefault(name, value) == value


# Solving -------------------------------------------------------------------------------------

def _tighten(bounds: Bounds, name: str, kind: str | None, value: Any, strict: bool,
             lower: bool) -> bool:
    """Add `name > value` (lower) or `name < value` (or >=, <=); False when the box empties."""
    if kind == "integer":
        if lower:
            value = math.floor(value) + 1 if strict else math.ceil(value)
        else:
            value = math.ceil(value) - 1 if strict else math.floor(value)
        strict = False
    b = bounds.get(name) or _UNBOUNDED
    # A new interval, never a change to one: a box is copied by copying its dict alone.
    if lower:
        if b[0] is None or value > b[0] or (value == b[0] and strict):
            b = bounds[name] = (value, strict, b[2], b[3])
    elif b[2] is None or value < b[2] or (value == b[2] and strict):
        b = bounds[name] = (b[0], b[1], value, strict)
    if b[0] is None or b[2] is None:
        return True
    return b[0] < b[2] or (b[0] == b[2] and not b[1] and not b[3])


def _solved(constant: Number, c: Number) -> Number:
    """The x of c x + constant = 0, exact (an int when integral)."""
    if type(constant) is int and type(c) is int:  # most bounds: no Fraction made
        if c == 1:
            return -constant
        if c == -1:
            return constant
        whole, left = divmod(-constant, c)
        return whole if left == 0 else Fraction(-constant, c)
    found: Number = exact(Fraction(-constant) / c)
    return found


def _range(terms: tuple[tuple[str, Fraction], ...], bounds: Bounds) -> tuple[Any, Any]:
    """The least and greatest value of sum(c * x) over the box's closure (None: unbounded)."""
    if len(terms) == 1:  # most formulas: the ends themselves, no sum made
        name, c = terms[0]
        b = bounds.get(name)
        if b is None:
            return None, None
        lo, hi = (b[2], b[0]) if c < 0 else (b[0], b[2])
        if c != 1:
            lo = None if lo is None else c * lo
            hi = None if hi is None else c * hi
        return lo, hi
    low: Number | None = 0
    high: Number | None = 0
    for name, c in terms:
        b = bounds.get(name)
        lo, hi = (b[0], b[2]) if b is not None else (None, None)
        if c < 0:
            lo, hi = hi, lo
        if c != 1:  # ints mostly: exact and far cheaper than Fraction arithmetic
            lo = None if lo is None else c * lo
            hi = None if hi is None else c * hi
        low = None if low is None or lo is None else low + lo
        high = None if high is None or hi is None else high + hi
    return low, high


def _simplify(f: Formula, bounds: Bounds, bools: Bools) -> Formula:
    """True or False when the formula holds on all or none of the box; else what is left.
    (Over the box's closure: a verdict there holds on the box too.)"""
    if f is True or f is False:
        return f
    tag = f[0]
    if tag == "a":
        low, high = _range(f[1], bounds)
        # sum + k against 0 is sum against -k: compared, not added (Fractions are slow made)
        edge, op = -f[2], f[3]
        if op == "<=":
            verdict = True if high is not None and high <= edge else (
                False if low is not None and low > edge else None)
        elif op == "<":
            verdict = True if high is not None and high < edge else (
                False if low is not None and low >= edge else None)
        else:
            equal = True if low == edge and high == edge else (
                False if (low is not None and low > edge) or (high is not None and high < edge)
                else None)
            verdict = equal if op == "=" or equal is None else not equal
        return f if verdict is None else verdict
    if tag == "b":
        value = bools.get(f[1])
        return f if value is None else value == f[2]
    if tag == "s":
        value = bools.get(f[1], _MISSING)
        return f if value is _MISSING else (value == f[2]) == f[3]
    return join(tag, [_simplify(p, bounds, bools) for p in f[1]])


def _propagate(formulas: list[Formula], bounds: Bounds, bools: Bools,
               kinds: Mapping[str, str], settled: Iterable[Formula] = ()
               ) -> list[Formula] | Literal[False]:
    """Tighten the box with every top-level bound until nothing changes; the formulas left,
    or False when some formula (or the box) cannot hold. `settled`: formulas already
    propagated in this box, looked at again only if the box shrinks. A formula simplified
    after the round's last tightening is settled too: the next round looks again only at
    those simplified before it."""
    settled = list(settled)
    for _ in range(100):  # each round tightens some bound; a cap keeps it finite
        changed = False
        rest: list[Formula] = []
        stale = 0  # rest[:stale] were simplified before the box last shrank
        work = list(formulas)
        while work:
            f = _simplify(work.pop(), bounds, bools)
            if f is True:
                continue
            if f is False:
                return False
            if f[0] == "&":
                work.extend(f[1])
            elif f[0] == "b" or (f[0] == "s" and f[3]):  # a Boolean, a text that is equal
                bools[f[1]] = f[2]
                changed, stale = True, len(rest)
            elif f[0] == "a" and len(f[1]) == 1 and f[3] != "!=":
                name, c = f[1][0]
                value, op = _solved(f[2], c), f[3]
                kind = kinds.get(name)
                ok = True
                if op == "=" or c > 0:  # c x + k <= 0: x <= -k / c
                    ok = _tighten(bounds, name, kind, value, op == "<", False)
                if ok and (op == "=" or c < 0):
                    ok = _tighten(bounds, name, kind, value, op == "<", True)
                if not ok:
                    return False
                changed, stale = True, len(rest)
            else:
                rest.append(f)
        if not changed:
            return rest + settled
        formulas, settled = rest[:stale] + settled, rest[stale:]
    return formulas + settled


def _solve(formulas: list[Formula], bounds: Bounds, bools: Bools,
           kinds: Mapping[str, str], splits: list[int], settled: Iterable[Formula] = ()
           ) -> bool | None:
    rest = _propagate(formulas, bounds, bools, kinds, settled)
    if rest is False:
        return False
    if not rest or any(_holds_at(rest, bounds, bools, kinds, corner) for corner in _CORNERS):
        return True
    for index, f in enumerate(rest):
        if f[0] != "|":
            continue
        others = rest[:index] + rest[index + 1:]
        unknown = False
        for part in f[1]:
            if splits[0] <= 0:
                return None
            splits[0] -= 1
            verdict = _solve([*others, part], dict(bounds),
                             dict(bools), kinds, splits)
            if verdict:
                return True
            unknown = unknown or verdict is None
        return None if unknown else False
    return None


_CORNERS = ("low", "high", "middle")


def _point(b: tuple[Any, ...] | None, kind: str | None, corner: str) -> Number:
    """A value inside one quantity's interval (its low end, high end or middle)."""
    lo, lo_strict, hi, hi_strict = b or _UNBOUNDED
    if corner == "low" and lo is not None and not lo_strict:
        value = lo
    elif corner == "high" and hi is not None and not hi_strict:
        value = hi
    elif lo is not None and hi is not None:
        value = Fraction(lo + hi) / 2
    elif lo is not None:
        value = lo + 1
    elif hi is not None:
        value = hi - 1
    else:
        value = 0
    if kind == "integer":
        floor: int = math.floor(value)
        return floor
    found: Number = exact(value)
    return found


def _holds_at(formulas: list[Formula], bounds: Bounds, bools: Bools,
              kinds: Mapping[str, str], corner: str) -> bool:
    """Whether every formula holds at one point of the box (a proof of satisfiability)."""
    at = _Corner(bounds, bools, kinds, corner)
    try:
        return all(map(at.holds, formulas))
    except Unsupported:  # no such point inside the box (an integer interval between values)
        return False


class _Corner:
    """One point of a box, each quantity's value chosen when first read. An object, not
    nested functions: a recursive closure is a reference cycle, left for the collector at
    every one of the thousands of calls."""

    __slots__ = ("bools", "bounds", "corner", "kinds", "point")

    def __init__(self, bounds: Bounds, bools: Bools, kinds: Mapping[str, str],
                 corner: str) -> None:
        self.bounds, self.bools, self.kinds, self.corner = bounds, bools, kinds, corner
        self.point: dict[str, Number] = {}

    def value(self, name: str) -> Number:
        found = self.point.get(name)
        if found is None:
            b = self.bounds.get(name)
            found = self.point[name] = _point(b, self.kinds.get(name), self.corner)
            if b is not None and not _inside(found, b):
                raise Unsupported
        return found

    def holds(self, f: Formula) -> bool:
        if f is True or f is False:
            return bool(f)
        if f[0] == "a":
            total = f[2] + sum(c * self.value(n) for n, c in f[1])
            return compare_constant(total, str(f[3]))
        if f[0] == "b":
            return bool(self.bools.get(f[1], self.corner == "high") == f[2])
        if f[0] == "s":  # a free string equals no text named (z3 may pick any other code)
            return bool((self.bools.get(f[1], _MISSING) == f[2]) == f[3])
        return (all if f[0] == "&" else any)(map(self.holds, f[1]))


def _inside(value: Number, b: tuple[Any, ...]) -> bool:
    lo, lo_strict, hi, hi_strict = b
    return ((lo is None or value > lo or (value == lo and not lo_strict))
            and (hi is None or value < hi or (value == hi and not hi_strict)))
