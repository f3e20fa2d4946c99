"""Where a refined mission's flat goals sit in the hierarchy, for traces and runs.

A refined goal is carried out by the goals of its refinement, so the flat mission graph holds
only those; this records what the flat graph forgets: the refined goals each flat goal runs
inside, and the refinements an outcome edge leaves (with the outcome each returns).
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Exit:
    """An outcome edge leaves the refinement of `parent` (a flat id such as `G1`), which
    thereby ends with `returns`; `timed_out` when its time-out ended it."""

    parent: str
    returns: str
    timed_out: bool = False


@dataclass(frozen=True)
class Nesting:
    # Flat goal id -> the refined goals it runs inside, outermost first: (flat id, label).
    parents: dict[str, tuple[tuple[str, str], ...]] = field(default_factory=dict)
    # (flat goal id, outcome) -> the refinements that edge leaves, innermost first.
    exits: dict[tuple[str, str], tuple[Exit, ...]] = field(default_factory=dict)
