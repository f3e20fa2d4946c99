"""The extension of a normal default theory, computed by forward chaining (seed 004, eq. 4).

Why forward chaining is exact here (no SAT solver needed)
--------------------------------------------------------
Every formula of the theory is a literal or a rule `l1 and ... and lk -> h` over literals, read
as an inference rule, as the seed's Prolog implementation reads W (no contraposition: from
"a leak means no shutdown" and "shut down" we must never conclude "no leak"). Rename each
negative literal `not p` to a fresh atom p' and add the integrity clauses `not (p and p')`.
The renamed W' is a set of Horn clauses: definite rules plus purely negative constraints, and
observations and default conclusions are positive atoms of the renamed vocabulary. For Horn
clauses unit propagation (here: counter-based forward chaining, linear in the rule size) is
sound and refutation-complete, so

  * the literals of Th(W' + E) are exactly the forward-chaining closure of E, and
  * a normal default's justification C is consistent with E  iff  the closure of E + {C}
    contains no pair p, p'.

Checking consistency against the closure *after* adding C (not merely "not C is absent") is
what keeps every step consistent, so the greedy construction below yields a Reiter extension
(semi-monotonicity of normal theories). `tests/rules/test_rules_properties.py` checks it against
the definition with z3 as the oracle on random theories.

Priorities (Brewka's prioritised default logic, as the seed resolves conflicts): strict rules
and exceptions act first and always; then the applicable default of highest rank is applied:
explicit `priority` (higher first), then the more specific default (more prerequisites: a
superset of prerequisites always ranks before its subset), then declaration order.

Contradictory observations: Reiter's only extension would then be the set of all formulas. A
vehicle still has to act, so the contradiction is reported and reasoning goes on around it:
a default is blocked only when its conclusion would add a *new* contradiction.
"""

from __future__ import annotations

import functools
import heapq
import itertools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from .syntax import Literal, is_variable, parse_atom, parse_literal
from .theory import DO_SAFE, GOAL, NEXT_ACTION, DefaultTheory, Rule

EQ17_ID = "eq17"
# Variables multiply rules by the constants they range over: bound the result, so that rules
# from untrusted orders cannot make the reasoner allocate without limit.
MAX_GROUND_RULES = 500_000


class TheoryTooLarge(ValueError):
    pass

EQ17_PRIORITY = -(10**7)  # below any priority a theory may state: safety rules come first
EQ17_RULE = Rule(
    id=EQ17_ID,
    kind="action",
    is_default=True,
    body=(Literal(NEXT_ACTION, "A"),),
    head=Literal(DO_SAFE, "A"),
    text="If nothing prevents the planned action, do it (seed 004 eq. 17).",
    priority=EQ17_PRIORITY,
)


@dataclass(frozen=True)
class Extension:
    """One extension: what the vehicle believes and must do, given the observations."""

    literals: frozenset[str]
    fired: tuple[str, ...]
    blocked: tuple[str, ...]
    safe_actions: tuple[str, ...]
    contradictions: tuple[str, ...] = ()
    observations: tuple[tuple[str, bool], ...] = ()
    # literal -> id of the rule that first derived it ("observed" for observations)
    derived_by: Mapping[str, str] = field(default_factory=dict, compare=False, repr=False)
    theory: DefaultTheory | None = field(default=None, compare=False, repr=False)
    # Literals derived plus rule prerequisites they satisfied (the seed's "inferences", Fig. 4b;
    # trials undone are not counted): a machine-independent measure of the work of a step.
    inferences: int = field(default=0, compare=False, repr=False)

    def holds(self, literal: str) -> bool:
        return str(parse_literal(literal)) in self.literals

    @property
    def consistent(self) -> bool:
        return not self.contradictions

    @property
    def goals(self) -> tuple[str, ...]:
        """Arguments of the goal(X) literals that hold, in sorted order."""
        prefix = f"{GOAL}("
        return tuple(
            sorted(lit[len(prefix):-1] for lit in self.literals if lit.startswith(prefix))
        )

    def observation_map(self) -> dict[str, bool]:
        return dict(self.observations)

    def to_json(self) -> dict[str, Any]:
        """For records and the API: what held, what fired, what was blocked, and why."""
        return {
            "observations": [[key, value] for key, value in self.observations],
            "literals": sorted(self.literals),
            "goals": list(self.goals),
            "safe_actions": list(self.safe_actions),
            "fired": list(self.fired),
            "blocked": list(self.blocked),
            "contradictions": list(self.contradictions),
            "derived_by": dict(sorted(self.derived_by.items())),
        }


# --------------------------------------------------------------------------------- grounding


@dataclass
class _Program:
    """The theory grounded over a set of constants, with literals as ints (2*atom + negated)."""

    atoms: dict[str, int]
    names: list[str]
    rule_ids: list[str]
    is_default: list[bool]
    body_len: list[int]
    head: list[int]
    rank: list[tuple[int, int, int]]
    watch: list[list[int]]
    start: list[int]  # rules with an empty body
    texts: list[str] = field(default_factory=list)  # literal index -> "p(a)" / "not p(a)"

    def literal_index(self, literal: Literal) -> int:
        atom = self.atoms.get(literal.atom)
        if atom is None:
            atom = len(self.names)
            self.atoms[literal.atom] = atom
            self.names.append(literal.atom)
            self.watch.append([])
            self.watch.append([])
        return 2 * atom + (0 if literal.positive else 1)

    def literal_text(self, index: int) -> str:
        atom = self.names[index >> 1]
        return atom if not index & 1 else f"not {atom}"

    def freeze(self) -> None:
        self.texts = [self.literal_text(i) for i in range(2 * len(self.names))]


def _constants_by_name(theory: DefaultTheory, extra: Iterable[Literal]) -> dict[str, set[str]]:
    by_name: dict[str, set[str]] = {}
    literals = itertools.chain(
        (lit for rule in theory.rules for lit in (*rule.body, rule.head)),
        theory.observables,
        extra,
    )
    for lit in literals:
        if lit.arg is not None and not is_variable(lit.arg):
            by_name.setdefault(lit.name, set()).add(lit.arg)
    # Any declared action, or one a rule may order, can be planned: ground eq. 17 and rules
    # reading next_action(X) for all of them up front, so that checking one more planned
    # action never recompiles the theory.
    plannable = set(theory.actions) | by_name.get(DO_SAFE, set())
    by_name.setdefault(DO_SAFE, set()).update(plannable)
    by_name.setdefault(NEXT_ACTION, set()).update(plannable)
    return by_name


def _ground(theory: DefaultTheory, rules: Iterable[Rule], extra: Iterable[Literal]) -> list[Rule]:
    """Ground rules with variables. A variable only ranges over the constants that can make its
    prerequisites true: those seen as argument of the same predicate (over-approximated by all
    constants when some rule concludes that predicate with a variable)."""
    by_name = _constants_by_name(theory, extra)
    everything = set().union(*by_name.values()) if by_name else set()
    open_heads = {
        rule.head.name for rule in (*theory.rules, EQ17_RULE) if rule.head.has_variable
    }
    ground: list[Rule] = []
    for rule in rules:
        variables = rule.variables
        if not variables:
            ground.append(rule)
            continue
        choices = []
        for variable in variables:
            domain: set[str] | None = None
            for lit in rule.body:
                if lit.arg == variable:
                    names = everything if lit.name in open_heads else by_name.get(lit.name, set())
                    domain = set(names) if domain is None else domain & names
            choices.append(sorted(everything if domain is None else domain))
        size = 1
        for choice in choices:
            size *= len(choice)
        if len(ground) + size > MAX_GROUND_RULES:
            raise TheoryTooLarge(
                f"{rule.path or rule.id}: grounding the variables gives more than "
                f"{MAX_GROUND_RULES} rules; use fewer variables or constants"
            )
        for values in itertools.product(*choices):
            body, head = rule.body, rule.head
            for variable, value in zip(variables, values, strict=True):
                body = tuple(lit.bind(variable, value) for lit in body)
                head = head.bind(variable, value)
            ground.append(
                Rule(rule.id, rule.kind, rule.is_default, body, head, rule.text,
                     rule.priority, rule.exception_to, rule.path)
            )
    return ground


def _compile(theory: DefaultTheory, extra: Iterable[Literal], with_eq17: bool) -> _Program:
    extra = list(extra)
    rules: list[Rule] = [*theory.facts, *theory.strict, *theory.defaults]
    if with_eq17:
        rules.append(EQ17_RULE)
    program = _Program({}, [], [], [], [], [], [], [], [])
    for order, rule in enumerate(_ground(theory, rules, extra)):
        index = len(program.rule_ids)
        body = tuple(dict.fromkeys(program.literal_index(lit) for lit in rule.body))
        program.rule_ids.append(rule.id)
        program.is_default.append(rule.is_default)
        program.body_len.append(len(body))
        program.head.append(program.literal_index(rule.head))
        program.rank.append((-rule.priority, -len(body), order))
        for lit in body:
            program.watch[lit].append(index)
        if not body:
            program.start.append(index)
    program.freeze()
    return program


def _program(theory: DefaultTheory, extra: list[Literal], with_eq17: bool) -> _Program:
    # Grounding depends only on which constants the observations add: cache per constant set,
    # so a vehicle stepping with the same vocabulary compiles its theory once.
    cache = theory._cache  # the theory owns its compiled forms
    known = cache.get("constants")
    if known is None:
        known = cache["constants"] = _constants_by_name(theory, ())
    new = frozenset(
        (lit.name, lit.arg) for lit in extra
        if lit.arg is not None and lit.arg not in known.get(lit.name, ())
    )
    key = (new, with_eq17)
    program = cache.get(key)
    if program is None:
        if len(cache) > 64:
            cache.clear()
            cache["constants"] = known
        program = _compile(theory, extra, with_eq17)
        cache[key] = program
    return program


# ------------------------------------------------------------------------------- extension


@functools.lru_cache(maxsize=100_000)
def _observed_atom(key: str) -> Literal:
    # The same observation keys come back every period: read each once.
    literal = parse_literal(key)
    if literal.has_variable:
        raise ValueError(f"observation {key!r}: an observation names no variable")
    return literal


def _observation_literals(observations: Mapping[str, bool]) -> list[Literal]:
    literals = []
    for key, value in observations.items():
        if not isinstance(value, bool):
            raise ValueError(f"observation {key!r}: expected true or false, got {value!r}")
        if not isinstance(key, str):
            raise ValueError(f"observation {key!r}: expected an atom as text")
        literal = _observed_atom(key)
        literals.append(literal if value else literal.negated())
    return literals


def compute(
    theory: DefaultTheory, observations: Mapping[str, bool], with_eq17: bool = False
) -> Extension:
    observed = _observation_literals(observations)
    program = _program(theory, observed, with_eq17)
    # The program is shared and read-only here (threads may step the same theory). Observed
    # atoms that no rule mentions cannot trigger anything: they are only carried along.
    atoms = program.atoms
    obs_index = [
        2 * atoms[lit.atom] + (0 if lit.positive else 1) for lit in observed if lit.atom in atoms
    ]
    loose = {str(lit): lit for lit in observed if lit.atom not in atoms}
    true = bytearray(2 * len(program.names))
    counts = list(program.body_len)
    trail: list[int] = []
    derived: dict[int, str] = {}
    fired: list[str] = []
    blocked: list[str] = []
    contradictions: list[int] = []
    agenda: list[tuple[tuple[int, int, int], int]] = []
    watch, heads = program.watch, program.head
    is_default, rule_ids = program.is_default, program.rule_ids

    def propagate(start: list[tuple[int, str]], pending: list[int], fired_now: list[str],
                  contradicted_ok: bool) -> bool:
        """Make literals true with their consequences; False on a new contradiction (the caller
        undoes). Defaults that become applicable go to `pending`."""
        queue = start
        while queue:
            lit, why = queue.pop()
            if true[lit]:
                continue
            if true[lit ^ 1]:
                if not contradicted_ok:
                    return False
                contradictions.append(lit >> 1)
            true[lit] = 1
            trail.append(lit)
            derived.setdefault(lit, why)
            for rule in watch[lit]:
                counts[rule] -= 1
                if counts[rule] == 0:
                    if is_default[rule]:
                        pending.append(rule)
                    else:
                        fired_now.append(rule_ids[rule])
                        queue.append((heads[rule], rule_ids[rule]))
        return True

    # W: observations, facts and strict rules. Contradictions here are reported, not fatal.
    start = [(lit, "observed") for lit in obs_index]
    pending: list[int] = []
    for rule in program.start:
        if is_default[rule]:
            pending.append(rule)
        else:
            fired.append(rule_ids[rule])
            start.append((heads[rule], rule_ids[rule]))
    start.reverse()  # the queue pops from the end: keep observations first
    propagate(start, pending, fired, contradicted_ok=True)
    for rule in pending:
        heapq.heappush(agenda, (program.rank[rule], rule))

    # D: the applicable default of highest rank, if its conclusion stays consistent.
    while agenda:
        _, rule = heapq.heappop(agenda)
        head = heads[rule]
        if true[head]:
            fired.append(rule_ids[rule])
            continue
        if true[head ^ 1]:
            blocked.append(rule_ids[rule])
            continue
        mark = len(trail)
        pending = []
        fired_now: list[str] = []
        if propagate([(head, rule_ids[rule])], pending, fired_now, contradicted_ok=False):
            fired.append(rule_ids[rule])
            fired.extend(fired_now)
            for new in pending:
                heapq.heappush(agenda, (program.rank[new], new))
            continue
        blocked.append(rule_ids[rule])
        while len(trail) > mark:  # undo the trial: the justification was inconsistent
            lit = trail.pop()
            true[lit] = 0
            derived.pop(lit, None)
            for watcher in watch[lit]:
                counts[watcher] += 1

    text_of = program.texts
    texts = [text_of[lit] for lit in trail]
    loose_contradictions = [
        lit.atom for lit in loose.values() if lit.positive and str(lit.negated()) in loose
    ]
    safe_prefix = f"{DO_SAFE}("
    safe = tuple(
        dict.fromkeys(text[len(safe_prefix):-1] for text in texts if text.startswith(safe_prefix))
    )
    fired_ids = tuple(dict.fromkeys(fired))
    derived_by = {text_of[lit]: why for lit, why in derived.items()}
    derived_by.update((text, "observed") for text in loose)
    return Extension(
        literals=frozenset(texts).union(loose),
        fired=fired_ids,
        blocked=tuple(b for b in dict.fromkeys(blocked) if b not in fired_ids),
        safe_actions=safe,
        contradictions=tuple(
            dict.fromkeys([*(program.names[atom] for atom in contradictions),
                           *loose_contradictions])
        ),
        # As given (normalised), so that check_action replays exactly the same observations.
        observations=tuple(
            (str(_observed_atom(key)), value) for key, value in observations.items()
        ),
        derived_by=derived_by,
        theory=theory,
        inferences=len(trail) + sum(len(watch[lit]) for lit in trail),
    )


def extension(theory: DefaultTheory, observations: Mapping[str, bool]) -> Extension:
    """The (prioritised) extension of `theory` given the observed truth values of atoms."""
    return compute(theory, observations)


def parse_observations(text: str) -> dict[str, bool]:
    """`gps=false,usbl=false,leak` -> {"gps": False, "usbl": False, "leak": True}."""
    result: dict[str, bool] = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        key, _, value = part.partition("=")
        atom = parse_atom(key.strip()).atom
        word = value.strip().lower() or "true"
        if word not in {"true", "false", "1", "0", "yes", "no"}:
            raise ValueError(f"observation {part!r}: the value must be true or false")
        result[atom] = word in {"true", "1", "yes"}
    return result
