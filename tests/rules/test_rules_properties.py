"""The extension engine against the definition of a Reiter extension, with z3 as the oracle
(propositional theories, and one-argument atoms with variables grounded naively).

Random small normal default theories (atoms a..e, literals with `not`, strict rules, defaults
with priorities, observations). The oracle knows nothing of forward chaining: it reads the
theory classically over the renamed vocabulary (`not p` is an atom p' with the constraint
not(p and p')), decides entailment and consistency with z3, and checks
  1. closure:  the engine's literals are exactly the literals W + E entails, and consistent;
  2. Reiter's fixpoint: Gamma(E), built naively from W by adding the conclusion of every default
     whose prerequisites Gamma already entails and whose justification is consistent with E,
     entails exactly E again (E = Gamma(E), the definition of an extension);
  3. priorities: a naive prioritised construction (repeatedly apply the best-ranked applicable
     default consistent with what is derived so far, checked by z3) reaches the same set.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import z3
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from countersign.rules import extension, parse_theory
from countersign.rules.syntax import parse_literal

ATOMS = ("a", "b", "c", "d", "e")
LITERALS = tuple([*ATOMS, *(f"not {a}" for a in ATOMS)])

literal = st.sampled_from(LITERALS)
body = st.lists(literal, max_size=2, unique=True)


@st.composite
def theories(draw: st.DrawFn) -> tuple[dict[str, Any], dict[str, bool]]:
    strict = [
        {"id": f"S{i}", "if": draw(body), "then": draw(literal)}
        for i in range(draw(st.integers(0, 4)))
    ]
    defaults = [
        {"id": f"D{i}", "if": draw(body), "then": draw(literal),
         "priority": draw(st.integers(0, 2))}
        for i in range(draw(st.integers(1, 6)))
    ]
    observed = draw(st.dictionaries(st.sampled_from(ATOMS), st.booleans(), max_size=3))
    return {"strict": strict, "defaults": defaults}, observed


class Oracle:
    """Classical reading of the renamed theory, decided by z3."""

    def __init__(self, data: dict[str, Any], observed: dict[str, bool],
                 atoms: tuple[str, ...] = ATOMS) -> None:
        self.literals = tuple([*atoms, *(f"not {a}" for a in atoms)])
        self.var = {lit: z3.Bool(lit.replace("not ", "neg_")) for lit in self.literals}
        self.base: list[z3.BoolRef] = [z3.Not(z3.And(self.var[a], self.var[f"not {a}"]))
                                       for a in atoms]
        for rule in data["strict"]:
            self.base.append(z3.Implies(z3.And(True, *(self.var[b] for b in rule["if"])),
                                        self.var[rule["then"]]))
        for atom, value in observed.items():
            self.base.append(self.var[atom if value else f"not {atom}"])
        self.defaults = data["defaults"]

    def consistent(self, lits: Iterable[str]) -> bool:
        solver = z3.Solver()
        solver.add(*self.base, *(self.var[lit] for lit in lits))
        return bool(solver.check() == z3.sat)

    def closure(self, lits: Iterable[str]) -> frozenset[str]:
        lits = list(lits)
        solver = z3.Solver()
        solver.add(*self.base, *(self.var[lit] for lit in lits))
        if solver.check() != z3.sat:
            return frozenset(self.literals)
        return frozenset(
            lit for lit in self.literals if solver.check(z3.Not(self.var[lit])) == z3.unsat
        )

    def gamma(self, candidate: frozenset[str]) -> frozenset[str]:
        derived: set[str] = set()
        while True:
            known = self.closure(derived)
            new = {
                d["then"] for d in self.defaults
                if set(d["if"]) <= known and d["then"] not in derived
                and self.consistent([*candidate, d["then"]])
            }
            if not new:
                return self.closure(derived)
            derived |= new

    def prioritised(self) -> frozenset[str]:
        ranked = sorted(
            enumerate(self.defaults),
            key=lambda item: (-item[1]["priority"], -len(set(item[1]["if"])), item[0]),
        )
        applied: list[str] = []
        done: set[int] = set()
        while True:
            known = self.closure(applied)
            for index, default in ranked:
                if index in done or not set(default["if"]) <= known:
                    continue
                done.add(index)
                if self.consistent([*applied, default["then"]]):
                    applied.append(default["then"])
                break
            else:
                return self.closure(applied)


def _normal(lits: Iterable[str]) -> frozenset[str]:
    return frozenset(str(parse_literal(lit)) for lit in lits)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(theories())
def test_extension_is_a_reiter_extension(case: tuple[dict[str, Any], dict[str, bool]]) -> None:
    data, observed = case
    oracle = Oracle(data, observed)
    assume(oracle.consistent([]))  # contradictory W: see test_rules.py (reported, not Reiter)
    ext = extension(parse_theory(data), observed)
    ours = _normal(ext.literals)
    assert not ext.contradictions
    assert oracle.consistent(ours)
    assert oracle.closure(ours) == ours, "closed under the rules"
    assert oracle.gamma(ours) == ours, "E = Gamma(E): grounded and every applicable default applied"
    assert oracle.prioritised() == ours, "the extension the priorities select"
    for rule_id in ext.blocked:
        default = next(d for d in data["defaults"] if d["id"] == rule_id)
        assert not oracle.consistent([*ours, default["then"]]), f"{rule_id} was blocked soundly"


# One-argument atoms with a variable: the oracle grounds every rule naively over the Herbrand
# universe (every constant the theory or the observations name); the engine grounds each
# variable only over the constants that can make its prerequisites true.
PREDICATES = ("p", "q", "r")
CONSTANTS = ("a", "b", "c")
unary = st.builds(
    lambda neg, name, arg: f"{'not ' if neg else ''}{name}({arg})",
    st.booleans(), st.sampled_from(PREDICATES), st.sampled_from([*CONSTANTS, "X"]),
)
unary_body = st.lists(unary, max_size=2, unique=True)


@st.composite
def unary_theories(draw: st.DrawFn) -> tuple[dict[str, Any], dict[str, bool]]:
    strict = [{"id": f"S{i}", "if": draw(unary_body), "then": draw(unary)}
              for i in range(draw(st.integers(0, 4)))]
    defaults = [{"id": f"D{i}", "if": draw(unary_body), "then": draw(unary),
                 "priority": draw(st.integers(0, 1))}
                for i in range(draw(st.integers(1, 5)))]
    observed = draw(st.dictionaries(
        st.builds(lambda n, c: f"{n}({c})", st.sampled_from(PREDICATES),
                  st.sampled_from(CONSTANTS)),
        st.booleans(), max_size=3))
    return {"strict": strict, "defaults": defaults}, observed


def _ground_naively(data: dict[str, Any], observed: dict[str, bool]) -> dict[str, Any]:
    texts = [*observed, *(lit for key in ("strict", "defaults") for rule in data[key]
                          for lit in (*rule["if"], rule["then"]))]
    universe = sorted({parse_literal(t).arg for t in texts} - {"X", None})

    def ground(rule: dict[str, Any], value: str) -> dict[str, Any]:
        swap = lambda lit: lit.replace("(X)", f"({value})")  # noqa: E731
        return {**rule, "if": sorted({swap(b) for b in rule["if"]}), "then": swap(rule["then"])}

    result: dict[str, Any] = {}
    for key in ("strict", "defaults"):
        result[key] = []
        for rule in data[key]:
            mentions = any("(X)" in lit for lit in (*rule["if"], rule["then"]))
            result[key].extend([ground(rule, v) for v in universe] if mentions else [rule])
    return result


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(unary_theories())
def test_grounded_extension_is_a_reiter_extension(
    case: tuple[dict[str, Any], dict[str, bool]],
) -> None:
    data, observed = case
    atoms = tuple(f"{n}({c})" for n in PREDICATES for c in CONSTANTS)
    ground = _ground_naively(data, observed)
    oracle = Oracle(ground, observed, atoms)
    assume(oracle.consistent([]))
    ext = extension(parse_theory(data), observed)
    ours = _normal(ext.literals)
    assert oracle.closure(ours) == ours
    assert oracle.gamma(ours) == ours
    assert oracle.prioritised() == ours
