"""A brute force for refined orders, written apart from verify.refine: it runs the
nested orders as an interpreter would, one outcome at a time in the order succeed, fail,
violate, keeping a stack of refinements with their own goal counts and seconds spent. It
yields every run with its flat goals, its trace lines and what each step costs."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any

from countersign.orders.model import OUTCOMES, Goal, Orders, Refinement
from countersign.verify.costs import leg_cost
from countersign.verify.legs import leg_lengths

QUESTION = "Did goal Succeed (s), Fail (f), or end with a Constraint (c)?"
ANSWER = {"succeed": "succeed", "fail": "fail", "violate": "constraint"}
END = {"complete": "Mission Complete!", "abort": "Mission Abort!"}


@dataclass(frozen=True)
class Frame:
    goals: dict[str, Goal]
    terminals: dict[str, Any]
    refinement: Refinement | None
    prefix: str
    parent: str | None  # the refined goal's id in the frame below
    label: str
    commenced: int = 0
    spent: Fraction = Fraction(0)

    def timed_out(self) -> bool:
        within = self.refinement.within if self.refinement else None
        if within is None:
            return False
        if within.steps is not None:
            return self.commenced >= within.steps
        return self.spent >= Fraction(repr(within.duration_s))


@dataclass(frozen=True)
class Run:
    goals: tuple[str, ...]  # flat ids without unrolling marks
    outcomes: tuple[str, ...]
    terminal: str
    kind: str
    lines: tuple[str, ...]
    steps: tuple[Goal, ...]

    def trace(self, index: int) -> str:
        return "\n".join([f"Ethical Mission Execution Trace #{index}:", "?- execute_mission.",
                          *self.lines, END[self.kind]])


def _seconds(goal: Goal) -> Fraction:
    value = goal.cost.duration_s if goal.cost else None
    return Fraction(repr(value)) if value is not None else Fraction(0)


def runs(orders: Orders) -> Iterator[Run]:
    top = Frame(orders.goal_index(), orders.terminal_index(), None, "", None, "")
    assert isinstance(orders.start, str)
    yield from _commence((top,), orders.start, (), (), (), ())


def _commence(frames: tuple[Frame, ...], local: str, goals: tuple[str, ...],
              outcomes: tuple[str, ...], lines: tuple[str, ...], steps: tuple[Goal, ...]
              ) -> Iterator[Run]:
    frame = replace(frames[-1], commenced=frames[-1].commenced + 1)
    frames = (*frames[:-1], frame)
    goal = frame.goals[local]
    pad = "  " * (len(frames) - 1)
    lines = (*lines, f"{pad}Commence: {goal.label.rstrip('.')}.")
    if goal.refines is not None:
        inner = goal.refines
        child = Frame({g.id: g for g in inner.goals}, {t.id: t for t in inner.terminals},
                      inner, frame.prefix + local + "/", local, goal.label)
        assert isinstance(inner.start, str)
        yield from _commence((*frames, child), inner.start, goals, outcomes, lines, steps)
        return
    for outcome in OUTCOMES:
        ended = (*frames[:-1], replace(frame, spent=frame.spent + _seconds(goal)))
        yield from _after(ended, local, outcome, (*goals, frame.prefix + local),
                          (*outcomes, outcome), (*lines, f"{pad}{QUESTION} {ANSWER[outcome]}."),
                          (*steps, goal))


def _after(frames: tuple[Frame, ...], local: str, outcome: str, goals: tuple[str, ...],
           outcomes: tuple[str, ...], lines: tuple[str, ...], steps: tuple[Goal, ...]
           ) -> Iterator[Run]:
    frame = frames[-1]
    target = frame.goals[local].next[outcome]
    assert isinstance(target, str)
    if target in frame.goals:
        if frame.timed_out():
            assert frame.refinement is not None and frame.refinement.on_timeout is not None
            pad = "  " * (len(frames) - 1)
            yield from _return(frames, frame.refinement.on_timeout, goals, outcomes,
                               (*lines, f"{pad}Time-out: {frame.label.rstrip('.')}."), steps)
        else:
            yield from _commence(frames, target, goals, outcomes, lines, steps)
    elif frame.refinement is None:
        yield Run(goals, outcomes, target, frame.terminals[target].kind, lines, steps)
    else:
        yield from _return(frames, frame.terminals[target].returns, goals, outcomes, lines,
                           steps)


def _return(frames: tuple[Frame, ...], outcome: str, goals: tuple[str, ...],
            outcomes: tuple[str, ...], lines: tuple[str, ...], steps: tuple[Goal, ...]
            ) -> Iterator[Run]:
    below = frames[:-1]
    pad = "  " * (len(below) - 1)
    parent = frames[-1].parent
    assert parent is not None
    yield from _after(below, parent, outcome, goals, outcomes,
                      (*lines, f"{pad}{QUESTION} {ANSWER[outcome]}."), steps)


class Legs:
    """Each leg priced on its own two-goal orders (same areas, so the same frame)."""

    def __init__(self, orders: Orders) -> None:
        self.orders = orders
        self.vehicle = orders.target_vehicle()
        self.cache: dict[tuple[int, str, int], float | None] = {}

    def metres(self, here: Goal, outcome: str, there: Goal) -> float | None:
        key = (id(here), outcome, id(there))
        if key not in self.cache:
            pair = self.orders.model_copy(update={
                "start": "X", "constraints": [], "properties": [],
                "goals": [here.model_copy(update={"id": "X", "next": {outcome: "Y"},
                                                  "refines": None}),
                          there.model_copy(update={"id": "Y", "next": {}, "refines": None})]})
            self.cache[key] = leg_lengths(pair).get(("X", outcome))
        return self.cache[key]

    def total(self, run: Run, quantity: str) -> float:
        total = 0.0
        for i, goal in enumerate(run.steps):
            own = getattr(goal.cost, quantity, None) if goal.cost else None
            total += own or 0.0
            if i + 1 < len(run.steps):
                total += leg_cost(self.metres(goal, run.outcomes[i], run.steps[i + 1]),
                                  quantity, self.vehicle)
        return total
