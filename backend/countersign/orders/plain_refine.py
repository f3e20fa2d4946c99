"""Plain-language refinements: "Goal 1 is carried out as: 1.1 ..., 1.2 ...".

A refined goal's sub-goals are numbered under it (1.1, 1.2; nested 1.2.1) by their position in
the refinement; each reads like a goal of the orders, and a terminal of the refinement reads as
the parent goal ending with the outcome it returns. The time-out is said in words, so the
supervisor reads the bound the counts were made under.
"""

from __future__ import annotations

from collections.abc import Iterator

from .model import OUTCOMES, Goal, Refinement, RefinementTerminal
from .plain import (
    _DEFAULT_TITLES,
    Names,
    _goal_details,
    _one_line,
    join_english,
    outcome_sentences,
)

_ENDS = {"succeed": "ends in success", "fail": "ends in failure",
         "violate": "ends with an imminent constraint violation"}
_TIMEOUT = {"fail": "fails", "violate": "ends with an imminent constraint violation"}


class _LevelNames(Names):
    """Names inside one refinement: local goals by their numbers, terminals by what the parent
    goal then does."""

    def __init__(self, outer: Names, parent: str, number: str, refinement: Refinement) -> None:
        self.areas = outer.areas
        self.parent = parent
        self.numbers: dict[str, str] = {}
        for position, goal in enumerate(refinement.goals, start=1):
            self.numbers.setdefault(goal.id, f"{number}.{position}")
        self.goal_numbers = {}
        self.ends: dict[str, RefinementTerminal] = {}
        for terminal in refinement.terminals:
            self.ends.setdefault(terminal.id, terminal)

    def goal(self, goal_id: str) -> str:
        number = self.numbers.get(goal_id)
        return f"Goal {number}" if number else f"{goal_id} (not a goal of this refinement)"

    def action(self, target: str) -> str:
        if target in self.numbers:
            return f"execute Goal {self.numbers[target]}"
        terminal = self.ends.get(target)
        if terminal is None:
            return f"go to {target}, which is neither a goal nor a terminal of this refinement"
        if terminal.returns not in OUTCOMES:
            return f"go to {target}, which returns no outcome of {self.parent}"
        title = _one_line(terminal.title).rstrip(".")
        said = f"{self.parent} {_ENDS[terminal.returns]}"
        return said if title.lower() in _DEFAULT_TITLES else f"{said} ({title})"


def refinement_paragraphs(goal: Goal, number: str, outer: Names) -> Iterator[str]:
    """The paragraphs that say how a refined goal is carried out (none for other goals)."""
    refinement = goal.refines
    if refinement is None:
        return
    parent = f"Goal {number}"
    names = _LevelNames(outer, parent, number, refinement)
    listed = [f"{number}.{position} {_one_line(g.title).rstrip('.') or g.id}"
              for position, g in enumerate(refinement.goals, start=1)]
    intro = f"{parent} is carried out as: {join_english(listed) or 'no goal'}"
    if refinement.procedure is not None:  # a library procedure, by name, version and digest
        intro = (f"{parent} is carried out by procedure {refinement.procedure} version "
                 f"{refinement.version} ({refinement.digest or 'no digest pinned'}): "
                 f"{join_english(listed) or 'no goal copied in from the library'}")
    start = refinement.start
    if isinstance(start, str):
        intro += f"; it starts with {names.goal(start)}."
    else:
        intro += "; the refinement names no single start goal."
    within = refinement.within
    if within is not None:
        bound = (f"{within.steps} goal{'s' if within.steps != 1 else ''} have commenced"
                 if within.steps is not None else
                 f"its goals have taken {within.duration_s:g} s")
        outcome = _TIMEOUT.get(refinement.on_timeout or "", "ends with no outcome said")
        intro += (f" Time-out: once {bound} inside it, no further goal commences and "
                  f"{parent} {outcome}.")
    yield intro
    for position, inner in enumerate(refinement.goals, start=1):
        inner_number = f"{number}.{position}"
        title = _one_line(inner.title).rstrip(".") or inner.id
        yield (f"Goal {inner_number}: {title}{_goal_details(inner, names)}. "
               f"{outcome_sentences(inner, names)}")
        yield from refinement_paragraphs(inner, inner_number, names)
