"""Unsatisfiable cores as English sentences."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from .constants import GOAL_KINDS
from .items import Part
from .results import Core


def join_words(phrases: Sequence[str]) -> str:
    if len(phrases) <= 1:
        return "".join(phrases)
    return ", ".join(phrases[:-1]) + " and " + phrases[-1]


def core_sentence(parts: Sequence[Part]) -> str:
    """'<what the goal is ordered to do>, but <what forbids it>.'"""
    lead = [p for p in parts if p.kind in GOAL_KINDS]
    rest = [p for p in parts if p.kind not in GOAL_KINDS]
    if not lead:
        lead, rest = rest[:1], rest[1:]
    text = join_words(_merged(lead))
    text += ", but " + join_words([p.phrase for p in rest]) if rest else ", which can never hold"
    return text[:1].upper() + text[1:] + "."


def _merged(parts: Sequence[Part]) -> list[str]:
    """Phrases, with a goal's later envelope bounds shortened: 'G1 is ordered at depth 0-5 m
    and distance to the nearest shipping lane 0-500 m'."""
    phrases: list[str] = []
    seen: set[str] = set()
    for part in parts:
        marker = " is ordered at "
        if part.kind == "envelope" and part.subject in seen and marker in part.phrase:
            phrases.append(part.phrase.split(marker, 1)[1])
            continue
        if part.kind == "envelope":
            seen.add(part.subject)
        phrases.append(part.phrase)
    return phrases


def _subjects(first: Sequence[str], parts: Iterable[Part], kinds: Iterable[str] | None = None
              ) -> list[str]:
    subjects = list(dict.fromkeys(first))
    wanted = set(kinds) if kinds is not None else None
    for part in parts:
        if (wanted is None or part.kind in wanted) and part.subject not in subjects:
            subjects.append(part.subject)
    return subjects


def _ids(parts: Iterable[Part], kind: str) -> list[str]:
    return list(dict.fromkeys(p.subject for p in parts if p.kind == kind))


def _core_details(core: Core) -> dict[str, Any]:
    return {"core": core.to_json(), "minimal": core.minimal}
