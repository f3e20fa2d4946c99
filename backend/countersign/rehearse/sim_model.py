"""The rehearsal simulation's settings and records: its constants, limits, events, faults,
runs, the vehicle's state, a goal's waypoints and the goal being run (`sim.py` runs them)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

from ..orders.model import Goal
from .geo import Point
from .monitor import GoalFacts

State = Literal["running", "waiting_for_outcome", "finished"]
FAULTS: tuple[str, ...] = ("gps_loss", "nav_drift", "leak", "low_energy", "contact_close")


class UnknownFault(ValueError):
    """A fault (or team member) the rehearsal does not have: the request's mistake, not the
    rehearsal's state."""
SEARCH_BEHAVIORS = frozenset({"area_search", "search", "survey", "patrol", "coverage"})
HOLD_BEHAVIORS = {"sample": 600.0, "rendezvous": 300.0, "loiter": 300.0, "observe": 300.0}
RECOVERY_BEHAVIORS = frozenset({"recover", "recovery", "return", "return_to_base", "go_home"})

DEFAULT_SPEED_MPS = 1.5
DEFAULT_POWER_W = 100.0
DEFAULT_CAPACITY_WH = 1_000.0
DEFAULT_DEPTH_M = 30.0
DEFAULT_SWATH_M = 200.0
DIVE_RATE_MPS = 0.5
RESERVE_FRACTION = 0.10  # of capacity, kept for the unexpected on the way home
STRONG_CURRENT_CHANCE = 0.20  # seed 001's experiment
STRONG_CURRENT_FACTOR = 2.0
NORMAL_CURRENT_MPS, STRONG_CURRENT_MPS = 0.1, 0.8
NAV_DRIFT_PER_M, FAULT_DRIFT_PER_M = 0.002, 0.03
GPS_FIX_ERROR_M, USBL_FIX_ERROR_M = 2.0, 3.0
USBL_PERIOD_S = 30.0
USBL_RANGE_M = 30_000.0
FIX_MEMORY_S = 300.0  # how long a fix counts as "was captured"
IMMINENT_S = 30.0  # a constraint that will fail within this many seconds is imminent
CHECK_PERIOD_S = 5.0  # rules and monitors run this often: well inside the imminence horizon
ALL_QUANTITIES = frozenset({
    "altitude_m", "latitude_deg", "longitude_deg", "lane_distance_m", "contact_distance_m",
    "contact_range_m", "contact_count", "base_distance_m", "current_mps",
})
ENERGY_CHECK_S = 60.0
CONTACT_CLOSE_M = 1_000.0
LOCALISATION_PRECISION_M = 5.0  # seed 004: "the localization precision drops under a threshold"
NAV_ERROR_HIGH_M = 10.0  # the exemplar's constraint 1
ALTITUDE_LOW_M = 3.0
# Safety actions the vehicle can obey while still doing a goal that takes it home: it changes
# depth and carries on. Any other safety action ends the goal.
POSTURE_ACTIONS = {"surface": 0.0, "ascend": None, "dive": None}
SCRIPTED_CUT = {"succeed": 1.0, "fail": 0.6, "violate": 0.4}
QUESTION = "Did goal Succeed (s), Fail (f), or end with a Constraint (c)?"  # DESIGN.md traces
FAULT_WORDS = {"gps_loss": "GPS loss", "nav_drift": "navigation drift", "leak": "leak",
               "low_energy": "low energy", "contact_close": "contact closing"}
REPEATABLE_FAULTS = frozenset({"contact_close", "low_energy"})


@dataclass(frozen=True)
class Limits:
    step_s: float = 1.0
    max_steps: int = 2_000_000  # about 23 simulated days
    max_goal_visits: int = 1_000  # per run: orders with a loop still end
    max_tour_paths: int = 100
    max_events: int = 5_000
    max_goal_s: float = 86_400.0


@dataclass(frozen=True)
class Event:
    t: float
    kind: str
    text: str
    goal: str | None = None
    data: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"t": round(self.t, 3), "kind": self.kind, "text": self.text}
        if self.goal is not None:
            out["goal"] = self.goal
        if self.data:
            out["data"] = self.data
        return out


@dataclass(frozen=True)
class FaultSpec:
    """`name`, `name@GOAL` (when that goal starts) or `name@SECONDS` (simulated time)."""

    name: str
    at_goal: str | None = None
    at_s: float | None = None

    @classmethod
    def parse(cls, text: str) -> FaultSpec:
        name, _, when = text.strip().partition("@")
        if name not in FAULTS:
            raise ValueError(f"unknown fault {name!r}; choose one of {', '.join(FAULTS)}")
        if not when:
            return cls(name)
        try:
            seconds = float(when)
        except ValueError:
            return cls(name, at_goal=when)
        if not math.isfinite(seconds) or seconds < 0:
            raise ValueError(f"fault time must be a non-negative number of seconds: {text!r}")
        return cls(name, at_s=seconds)

    def __str__(self) -> str:
        if self.at_goal is not None:
            return f"{self.name}@{self.at_goal}"
        if self.at_s is not None:
            return f"{self.name}@{self.at_s:g}"
        return self.name


@dataclass
class Run:
    """One traversal from the start goal to a terminal (a tour has several)."""

    path_index: int | None = None
    goals: list[str] = field(default_factory=list)
    outcomes: list[str] = field(default_factory=list)
    terminal: str | None = None
    terminal_kind: str | None = None

    def to_json(self) -> dict[str, Any]:
        return {
            "path_index": self.path_index,
            "goals": list(self.goals),
            "outcomes": list(self.outcomes),
            "terminal": self.terminal,
            "terminal_kind": self.terminal_kind,
        }


@dataclass
class Vehicle:
    x: float
    y: float
    depth: float = 0.0
    heading: float = 0.0  # radians, x east / y north
    vx: float = 0.0
    vy: float = 0.0
    vz: float = 0.0
    nav_error_m: float = GPS_FIX_ERROR_M
    last_gps_s: float = 0.0
    last_usbl_s: float = -math.inf
    gps_now: bool = True
    usbl_now: bool = False
    forced_surface: bool = False  # a safety action brought it up; it stays up
    target_depth: float = 0.0

    @property
    def xy(self) -> Point:
        return (self.x, self.y)


@dataclass
class Waypoint:
    x: float
    y: float
    depth: float
    hold_s: float = 0.0
    kind: str = "transit"  # "leg": the transit from the previous goal (verify/legs' leg)
    geo_m: float = 0.0  # geodesic metres of the segment that ends here
    scale: float = 1.0  # geodesic metres per metre of the frame on that segment


@dataclass
class ActiveGoal:
    goal: Goal
    facts: GoalFacts
    waypoints: list[Waypoint]
    planned_s: float
    rate_wh_per_m: float
    hold_w: float
    started_s: float
    index: int = 0
    held_s: float = 0.0
    done_s: float = 0.0  # plan-time completed (metres / speed plus holds)
    used_wh: float = 0.0
    strong_current: tuple[float, float] | None = None  # (from, until) simulated seconds
    scripted: str | None = None
    suggestion: tuple[str, str] | None = None  # (outcome, reason) seen in manual mode
    last_energy_check: float = -math.inf
    leg_m: float = 0.0  # geodesic metres flown on the leg into this goal
    speed: float = DEFAULT_SPEED_MPS  # over the goal's own work (legs are flown at cruise)

    @property
    def progress(self) -> float:
        return 1.0 if self.planned_s <= 0 else min(1.0, self.done_s / self.planned_s)

    @property
    def finished_plan(self) -> bool:
        return self.index >= len(self.waypoints)
