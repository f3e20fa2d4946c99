"""Temporal patterns of path properties (verify.patterns) as plain sentences."""

from __future__ import annotations

from .model import Event, PathProperty


def event_words(event: Event | None) -> str:
    if event is None:
        return "(nothing)"
    parts: list[str] = []

    def alternatives(value: str | list[str]) -> str:
        return " or ".join(value) if isinstance(value, list) else value

    if event.goal is not None:
        parts.append(f"goal {alternatives(event.goal)}")
    if event.behavior is not None:
        parts.append(f"a {alternatives(event.behavior).replace('_', ' ')} goal")
    if event.outcome is not None:
        verbs = {"succeed": "succeeds", "fail": "fails", "violate": "ends with a violation"}
        names = event.outcome if isinstance(event.outcome, list) else [event.outcome]
        outcome = " or ".join(verbs[o] for o in names)
        parts.append(outcome if parts else f"a goal {outcome}")
    if event.terminal is not None:
        parts.append(f"the mission ends at {alternatives(event.terminal)}")
    if event.kind is not None:
        parts.append(f"the mission ends in {'completion' if event.kind == 'complete' else 'abort'}")
    return " ".join(parts) if parts else "anything"


def pattern_sentence(prop: PathProperty) -> str:
    """The pattern in plain words, as one sentence."""
    p, s = event_words(prop.p), event_words(prop.s)
    bound = ""
    for quantity, unit in (("steps", "goals"), ("duration_s", "s"), ("energy_wh", "Wh")):
        limit = getattr(prop.within, quantity) if prop.within is not None else None
        if limit is not None:
            bound = f" within {limit:g} {unit}"
            break
    body = {
        "absence": f"it never happens that {p}",
        "existence": f"at some point {p}",
        "universality": f"at every step {p}",
        "precedence": f"{p} only after {s}",
        "response": f"whenever {p}, then eventually {s}",
        "bounded_response": f"whenever {p}, then {s}{bound}",
    }[prop.pattern or "absence"]
    scope = {
        "globally": "On every path",
        "before": f"On every path, before {event_words(prop.r)}",
        "after": f"On every path, after {event_words(prop.q)}",
        "between": f"On every path, between {event_words(prop.q)} and {event_words(prop.r)}",
    }[prop.scope]
    return f"{scope}, {body}."
