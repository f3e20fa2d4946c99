"""What a check of a unit found: cores, risks, vacuity."""

from __future__ import annotations

from dataclasses import dataclass

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
