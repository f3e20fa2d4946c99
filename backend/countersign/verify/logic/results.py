"""What a check of a unit found: cores, risks, vacuity."""

from __future__ import annotations

from dataclasses import dataclass

from ...orders.findings import Finding
from .items import Part


@dataclass(frozen=True)
class Core:
    parts: tuple[Part, ...]
    minimal: bool

    def to_json(self) -> list[dict[str, str]]:
        return [p.to_json() for p in self.parts]


@dataclass(frozen=True)
class MissionResult:
    cores: tuple[Core, ...]
    quarantined: frozenset[str]
    undecided: str | None


@dataclass(frozen=True)
class Risk:
    norm: Part
    witness: tuple[tuple[str, str], ...]


@dataclass(frozen=True)
class GoalResult:
    contradictions: tuple[Core, ...]
    refusals: tuple[Core, ...]
    risks: tuple[Risk, ...]
    undecided: str | None


@dataclass(frozen=True)
class VacuousResult:
    core: Core | None
    undecided: str | None


@dataclass(frozen=True)
class GoalOutcome:
    """A goal's unit key and result, with the findings worded from them: carried to the model
    of the next version of the orders when the edit left the goal and everything else its
    unit reads as it was, so that an unchanged goal costs one cache look-up, not its items'
    key and its findings' words again."""

    key: str
    result: GoalResult
    # The goal's own findings, in the order the report lists them.
    findings: tuple[Finding, ...]
    # Contradictions with no statement of the goal's: reported once for every goal they stop.
    shared: tuple[Core, ...]
