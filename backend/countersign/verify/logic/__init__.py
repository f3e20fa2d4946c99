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
goal. Every solver call has a timeout and the whole run a budget of CPU time under a wall-clock
cap (limits.py); an undecided check is a warning finding, never a hang. z3 is imported and a
context created only when some unit misses the cache.

One module per job: items and model (a goal's facts in facts.py), the z3 session, the screen,
bounds propagation (and its formulas), unique cores, the cache, a run, wording, the findings
(a check pauses the cyclic garbage collector: collector.py) and the goal-set API.
`findings.BATCH_VACUITY` switches batched vacuity checks, `run.GROUP_CHECKS` the fast route:
the screen (screen.py: status-only checks, first by bounds propagation without z3, bounds.py,
else of terms parsed once per context, one answer shared by every goal with the same
formulas; a unit whose answer is more than "fine" is solved by the session as before), a
core's shrinking taking its "sat" answers from bounds.py, and a goal's core taken without z3
when it is proven the only one (unique.py). Every answer of the fast route is proven; the z3
route is its reference (tests/verify/test_logic_grouped.py, test_logic_bounds.py).

A check costs z3 time in proportion to everything asserted, so only what every goal assumes
(mission-wide constraints, the vehicle, domains, norms) stays asserted between goals; the rest
is asserted in the goal's own push/pop scope. Witness values are solved again in a context of
the unit's own, so that they depend on the unit's items only, not on what the session checked
before (re-validating with a warm cache gives the report a cold run gives).
"""

from __future__ import annotations

from .cache import LogicCache, unit_key
from .constants import (
    DEFAULT_TIMEOUT_MS,
    DEFAULT_TOTAL_S,
    GOAL_KINDS,
    MAX_CORES_PER_UNIT,
    MAX_WORDS,
    VERSION,
    ItemKind,
)
from .findings import check_logic, core_satisfiable
from .goal_set import GoalSetResult, UnknownIds, explain_goal_set, format_goal_set
from .items import Item, Part, expr_formula
from .limits import (
    BUDGET_SPENT,
    OUT_OF_TIME,
    THREAD_CLOCKS,
    WALL_CAP_FACTOR,
    WALL_CAP_REACHED,
    Clocks,
    Limits,
)
from .model import LogicModel, ParsedConstraint, ParsedNorm
from .results import Core, GoalResult, MissionResult, Risk, VacuousResult
from .run import LogicRun, sorted_parts
from .session import CheckResult, Session
from .wording import core_sentence, join_words

__all__ = [
    "BUDGET_SPENT",
    "DEFAULT_TIMEOUT_MS",
    "DEFAULT_TOTAL_S",
    "GOAL_KINDS",
    "MAX_CORES_PER_UNIT",
    "MAX_WORDS",
    "OUT_OF_TIME",
    "THREAD_CLOCKS",
    "VERSION",
    "WALL_CAP_FACTOR",
    "WALL_CAP_REACHED",
    "CheckResult",
    "Clocks",
    "Core",
    "GoalResult",
    "GoalSetResult",
    "Item",
    "ItemKind",
    "Limits",
    "LogicCache",
    "LogicModel",
    "LogicRun",
    "MissionResult",
    "ParsedConstraint",
    "ParsedNorm",
    "Part",
    "Risk",
    "Session",
    "UnknownIds",
    "VacuousResult",
    "check_logic",
    "core_satisfiable",
    "core_sentence",
    "explain_goal_set",
    "expr_formula",
    "format_goal_set",
    "join_words",
    "sorted_parts",
    "unit_key",
]
