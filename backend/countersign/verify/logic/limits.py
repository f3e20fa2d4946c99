"""The solver's time limits: CPU time of the work, under a hard wall-clock cap.

On a machine shared with other work the wall time of a check stretches with the load while the
work stays the same, so a budget in wall seconds decided all of a mission on a quiet machine and
left most of it undecided on a busy one. The budget therefore counts the CPU time of the thread
doing the work (z3 solves in the calling thread, so its time is counted too), and what a
validation decides no longer depends on what else the machine runs.

A validation must still end: its process serves other users next. A separate wall-clock cap
(by default `WALL_CAP_FACTOR` times the CPU budget) ends the work however little CPU it got,
and what it leaves is reported undecided with that reason, never as the solver's difficulty.

One solver call's own timeout stays wall time (z3 runs a timer), and the same from call to call:
changing it resets z3's parameters, after which the same question can get another core, so a
timeout stretched with the load would make the findings depend on the load. A call that the
limits cut short is reported undecided for that reason, not for its own difficulty.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

# The wall-clock cap's default, as a multiple of the CPU budget: an 8 s budget ends by 32 s
# whatever the load.
WALL_CAP_FACTOR = 4.0
# Reasons a unit is left undecided by the limits rather than by its own difficulty.
BUDGET_SPENT = "time budget exhausted"
WALL_CAP_REACHED = "wall-clock cap reached"
OUT_OF_TIME = frozenset({BUDGET_SPENT, WALL_CAP_REACHED})


@dataclass(frozen=True)
class Clocks:
    """Where the limits read time: the work's CPU time and wall time, in seconds. Tests pass
    clocks of their own to play a loaded machine deterministically."""

    cpu: Callable[[], float] = time.thread_time
    wall: Callable[[], float] = time.monotonic


THREAD_CLOCKS = Clocks()


@dataclass
class Limits:
    """One run's limits (check_logic and check_properties of one validation share one).
    Read from the thread that started them: the CPU clock is that thread's."""

    per_call_ms: int
    budget_s: float
    wall_cap_s: float
    clocks: Clocks = THREAD_CLOCKS
    _cpu_start: float = field(default=0.0, repr=False)
    _wall_start: float = field(default=0.0, repr=False)
    # Which limit shortened the last call's timeout (it may end undecided for that reason).
    _last_cut: str | None = field(default=None, repr=False)

    @classmethod
    def start(cls, per_call_ms: int, total_s: float, wall_cap_s: float | None = None,
              clocks: Clocks = THREAD_CLOCKS) -> Limits:
        """Limits from now: `total_s` seconds of CPU time, ended after `wall_cap_s` seconds
        of wall time (default `WALL_CAP_FACTOR` times `total_s`) in any case."""
        cap = WALL_CAP_FACTOR * total_s if wall_cap_s is None else wall_cap_s
        return cls(per_call_ms, total_s, cap, clocks, clocks.cpu(), clocks.wall())

    def _used(self) -> tuple[float, float]:
        return self.clocks.cpu() - self._cpu_start, self.clocks.wall() - self._wall_start

    def call_timeout_ms(self) -> int:
        """The wall-clock timeout of the next solver call: `per_call_ms`, or less when the CPU
        budget or the wall cap leaves less; 0 when either is reached."""
        cpu, wall = self._used()
        cpu_left, wall_left = self.budget_s - cpu, self.wall_cap_s - wall
        if cpu_left <= 0 or wall_left <= 0:
            return 0
        own = self.per_call_ms / 1000
        timeout = min(own, cpu_left, wall_left)
        self._last_cut = (None if timeout >= own else
                          WALL_CAP_REACHED if timeout == wall_left else BUDGET_SPENT)
        return max(1, int(timeout * 1000))

    def timed_out(self) -> str:
        """Why the last call ended in a timeout: a limit that shortened it, else its own."""
        return self.spent() or self._last_cut or f"timeout after {self.per_call_ms:,} ms"

    def spent(self) -> str | None:
        """Why no more solver work may be done (BUDGET_SPENT or WALL_CAP_REACHED), or None."""
        cpu, wall = self._used()
        if wall >= self.wall_cap_s:
            return WALL_CAP_REACHED
        if cpu >= self.budget_s:
            return BUDGET_SPENT
        return None
