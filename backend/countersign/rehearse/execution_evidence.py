"""What an execution log evidences: the times of each goal run, checked for being possible, and
which constraints in scope were read.

A run is only "no deviation" when it shows it: each goal run has a start and an end time, and
for each constraint in scope of a goal run some reading (or sample) lets the constraint be
evaluated. A log without them is not a deviation but "unverified", and says what is missing.

Times that cannot be real are errors, not evidence: text that is no time, an ISO 8601 time
without a zone, an end before its start or a goal starting before the one before it ended,
an absolute time after the present (plus clock skew) or before the approval, and relative
seconds (a MOOS alog's, a simulation's) that span more than the window."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any, Protocol


class ExecutionLogError(ValueError):
    """A log that cannot be read at all (the message names the line or step)."""


class TimedStep(Protocol):
    @property
    def goal(self) -> str: ...

    @property
    def time(self) -> str | None: ...

    @property
    def start(self) -> str | None: ...


@dataclass(frozen=True)
class TimeWindow:
    """Where a run's absolute times may lie, in POSIX seconds: not before `not_before` (the
    approval, when known) nor after `not_after` (the present plus clock skew)."""

    not_before: float | None
    not_after: float

    @classmethod
    def of(cls, *, now: datetime, skew_s: float, not_before: datetime | None = None
           ) -> TimeWindow:
        return cls(None if not_before is None else _posix(not_before),
                   _posix(now) + skew_s)


def _posix(moment: datetime) -> float:
    # Database rows keep UTC without a zone.
    return moment.timestamp() if moment.tzinfo is not None else \
        (moment - datetime(1970, 1, 1)).total_seconds()


@dataclass(frozen=True)
class Evidence:
    untimed: tuple[int, ...] = ()  # steps without both a start and an end time
    unread: tuple[tuple[str, int], ...] = ()  # (constraint, step) evaluated by no reading
    read: tuple[str, ...] = ()  # constraints in scope read at every step they apply to

    @property
    def complete(self) -> bool:
        return not self.untimed and not self.unread

    def unread_constraints(self) -> list[str]:
        return sorted({constraint for constraint, _ in self.unread})

    def gaps(self) -> list[str]:
        """What is missing, e.g. ["no times for steps 2, 3", "no readings for C1, C4"]."""
        gaps = []
        if self.untimed:
            plural = "s" if len(self.untimed) > 1 else ""
            gaps.append(f"no start and end times for step{plural} "
                        f"{_listed(str(s) for s in self.untimed)}")
        if self.unread:
            gaps.append(f"no readings for {_listed(self.unread_constraints())}")
        return gaps

    def to_json(self) -> dict[str, Any]:
        return {"complete": self.complete, "timed": not self.untimed,
                "untimed_steps": list(self.untimed[:MAX_LISTED]),
                "constraints_read": list(self.read),
                "constraints_unread": self.unread_constraints(), "gaps": self.gaps()}


MAX_LISTED = 20


def _listed(items: Any) -> str:
    shown = list(items)
    more = f" (and {len(shown) - MAX_LISTED} more)" if len(shown) > MAX_LISTED else ""
    return ", ".join(shown[:MAX_LISTED]) + more


def _moment(text: str, where: str) -> tuple[float, bool]:
    """(seconds, absolute) of an ISO 8601 time with a zone or a number of seconds."""
    try:
        seconds = float(text)
    except ValueError:
        pass
    else:
        if not math.isfinite(seconds):
            raise ExecutionLogError(f"{where}: {text[:40]!r} is not a finite number of seconds")
        return seconds, False
    try:
        moment = datetime.fromisoformat(text.replace("Z", "+00:00"))
    except ValueError:
        raise ExecutionLogError(f"{where}: {text[:40]!r} is not an ISO 8601 time or a number "
                                "of seconds") from None
    if moment.tzinfo is None:
        raise ExecutionLogError(f"{where}: {text[:40]!r} has no time zone (add Z or +hh:mm)")
    return moment.timestamp(), True


def _iso(seconds: float) -> str:
    return datetime.fromtimestamp(seconds, UTC).isoformat().replace("+00:00", "Z")


def check_times(steps: Sequence[TimedStep], window: TimeWindow | None) -> tuple[int, ...]:
    """The steps without both times; raise `ExecutionLogError` for times that cannot be."""
    untimed: list[int] = []
    kinds: set[bool] = set()
    previous: tuple[float, str] | None = None
    first: float | None = None
    for number, step in enumerate(steps, 1):
        if step.start is None or step.time is None:
            untimed.append(number)
        for name, text in (("start", step.start), ("time", step.time)):
            if text is None:
                continue
            where = f"step {number} ({step.goal[:40]}) {name}"
            seconds, absolute = _moment(text, where)
            kinds.add(absolute)
            if len(kinds) > 1:
                raise ExecutionLogError(f"{where}: the log mixes ISO 8601 times and numbers "
                                        "of seconds")
            if previous is not None and seconds < previous[0]:
                raise ExecutionLogError(f"{where}: {text[:40]} is before {previous[1]} (times "
                                        "must not run backwards)")
            _within(seconds, absolute, window, where, first)
            first = seconds if first is None else first
            previous = (seconds, f"the {name} {text[:40]} of step {number}")
    return tuple(untimed)


def _within(seconds: float, absolute: bool, window: TimeWindow | None, where: str,
            first: float | None) -> None:
    if not absolute:
        # Relative seconds have their own origin (a MOOS alog's is when pLogger started, so
        # the first entries can be negative): only their span can be bounded.
        span = seconds - (first if first is not None else seconds)
        if window is not None and window.not_before is not None and \
                span > window.not_after - window.not_before:
            raise ExecutionLogError(f"{where}: the run would have lasted {span:,.0f} s, longer "
                                    "than the time since its approval")
        return
    if window is None:
        return
    if seconds > window.not_after:
        raise ExecutionLogError(f"{where}: {_iso(seconds)} is in the future (beyond the "
                                "allowed clock skew)")
    if window.not_before is not None and seconds < window.not_before:
        raise ExecutionLogError(f"{where}: {_iso(seconds)} is before the orders were "
                                f"approved ({_iso(window.not_before)})")
