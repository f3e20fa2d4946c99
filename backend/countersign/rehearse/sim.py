"""The rehearsal simulation: one vehicle executing the orders goal by goal in a seeded world.

Deterministic given the orders, the seed, the outcome source and the faults (live injections
and manual choices happen between steps and are recorded with their simulated time). Pure
Python; the viser scene only reads the state this module exposes.

Each goal becomes a plan of waypoints (transit to the area at the goal's operating depth, then
the behaviour: lawn-mower legs for searches, a hold for samples and rendezvous, a straight run
for transects, a surfacing for recovery). Each step moves the vehicle, spends energy,
updates navigation error, moves the surface contacts, then asks in order:
1. the default rules (seed 004): a planned action the extension refuses ends the goal;
2. the constraint monitors: an imminent violation ends the goal with `violate` (EC1);
3. the energy check (seed 001): a goal that can no longer be finished with the reserve to
   reach recovery is given up (`fail`);
4. the plan: all waypoints done means `succeed`.
Which of these may end a goal depends on the outcome source (see `sources.py`).

Energy and time are charged from the verifier's cost model (verify/costs.py), so that the
verifier's figure for a path bounds what a nominal rehearsal of that path uses (issue 19):
- the mission starts where its start goal starts (the verifier charges no launch transit);
- a leg is charged as `leg_cost` charges it: geodesic metres at the vehicle's power and speed;
- a goal's own work (its sweep, run or holds) is charged exactly its `goal_cost` (given, or
  estimated as the verifier estimates it) when its plan runs to the end, spread over the work
  in proportion to time, and paced so that it takes no longer than its duration cost; a goal
  cut short is charged for the part it ran;
- time is what the metres and holds take: a step's time carries on past a waypoint reached
  within it, the step ends early when the goal's plan is done, and diving or rising happens
  while the vehicle moves, never holding the plan up (the verifier charges no time for it).
- seed 001's strong opposing current (doubling consumption) is a disturbance, outside the
  nominal case that the verifier bounds: only the `simulate` source, whose outcomes the
  simulation decides, meets it. The normal current is the nominal consumption itself.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

from ..orders.model import OUTCOMES, Area, Goal, Orders
from ..verify.costs import goal_cost
from ..verify.expressions import identifiers
from ..verify.legs import GEOD
from .contingency import Contingency, RuleVerdict
from .geo import Point, contains
from .monitor import GoalFacts, Monitor, facts_of, monitors_of
from .sources import OutcomeSource
from .world import FAR_M, World

State = Literal["running", "waiting_for_outcome", "finished"]
FAULTS: tuple[str, ...] = ("gps_loss", "nav_drift", "leak", "low_energy", "contact_close")
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
    expected_wh: float = 0.0  # energy the plan would use at normal consumption
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


class Simulation:
    def __init__(
        self,
        orders: Orders,
        *,
        seed: int = 0,
        source: OutcomeSource,
        faults: Sequence[str | FaultSpec] = (),
        limits: Limits | None = None,
        contingency: Contingency | None = None,
        charts: Sequence[Area] = (),
    ) -> None:
        self.orders = orders
        self.seed = seed
        self.limits = limits or Limits()
        self.rng = random.Random(seed)
        self.world = World(orders, self.rng, tuple(charts))
        self.source = source
        self.goals = orders.goal_index()
        self.terminals = orders.terminal_index()
        self.monitors, self.unmonitored = monitors_of(orders)
        self.needed = frozenset(q for m in self.monitors for q in identifiers(m.expr))
        self._next_check_s = 0.0
        self.contingency = contingency if contingency is not None else Contingency.for_orders(
            orders
        )
        self.contingency_actions = self.contingency.actions()
        vehicle = orders.target_vehicle()
        self.speed = vehicle.speed_mps if vehicle and vehicle.speed_mps else DEFAULT_SPEED_MPS
        self.power_w = vehicle.power_w if vehicle and vehicle.power_w else DEFAULT_POWER_W
        budget = vehicle.budget.energy_wh if vehicle and vehicle.budget else None
        self.capacity_wh = float(budget) if budget else DEFAULT_CAPACITY_WH
        self.detection_range_m = 6_000.0
        if vehicle and "contact_detection_range_m" in vehicle.envelope:
            self.detection_range_m = float(vehicle.envelope["contact_detection_range_m"][1])
        self._initial_faults: tuple[FaultSpec, ...] = tuple(
            f if isinstance(f, FaultSpec) else FaultSpec.parse(f) for f in faults
        )
        self.pending_faults: list[FaultSpec] = list(self._initial_faults)
        self.active_faults: set[str] = set()
        # Faults pressed while a goal waits for its outcome: applied when the next goal starts.
        self.queued_faults: list[str] = []
        self.fault_log: list[str] = []  # name@simulated-seconds, as activated
        self.choices: list[dict[str, Any]] = []
        self.events: list[Event] = []
        self.events_dropped = 0
        self.rule_firings: dict[str, int] = {}
        self.runs: list[Run] = []
        self.time_s = 0.0
        self.steps = 0
        self.energy_used_wh = 0.0
        self.expected_used_wh = 0.0
        self.state: State = "running"
        self._strong_current = False
        self._transect_areas = sorted({g.area for g in orders.goals
                                       if g.area and (g.behavior or "").lower() == "transect"})
        self._transects_done: set[str] = set()
        self.active: ActiveGoal | None = None
        self.vehicle = Vehicle(*self._launch_point())
        self.trail: list[tuple[float, float, float]] = []
        # The legs flown between goals: from, outcome, to and geodesic metres (issue 21).
        self.flown_legs: list[dict[str, Any]] = []
        self.leg_rate_wh_per_m = self.power_w / self.speed / 3600.0  # verify/costs' leg cost
        # Per-metre rates of the goals run so far: the price of the way home (seed 001 plans
        # with the consumption it has learnt, not with a catalogue figure).
        self._priced_m = 0.0
        self._priced_wh = 0.0
        self.listeners: list[Callable[[Event], None]] = []
        self._start_run()

    # ------------------------------------------------------------------------------ public

    @property
    def energy_remaining_wh(self) -> float:
        return max(0.0, self.capacity_wh - self.energy_used_wh)

    @property
    def current_goal(self) -> str | None:
        return self.active.goal.id if self.active else None

    @property
    def run(self) -> Run:
        return self.runs[-1]

    def advance(self, seconds: float) -> None:
        """Step until `seconds` of simulated time passed, the source waits for a choice, or
        the rehearsal ends."""
        target = self.time_s + seconds
        while self.state == "running" and self.time_s < target - 1e-9:
            self.step()

    def step(self) -> None:
        if self.state != "running":
            return
        if self.steps >= self.limits.max_steps:
            self._finish(f"stopped after {self.limits.max_steps} steps (the step bound)")
            return
        self.steps += 1
        dt = self.limits.step_s
        self.time_s += dt
        self._scheduled_faults()
        active = self.active
        if active is None:
            return
        # A step ends early when the goal's plan is done within it: the goal then ends when
        # its work does, and the next goal starts there (a goal takes its plan's time, not
        # that time rounded up to the step).
        unused = self._move(active, dt)
        if unused > 0.0:
            self.time_s -= unused
            dt -= unused
        self._navigate(dt)
        self._judge(active)
        self._scheduled_faults(after_step=True)

    def choose(self, outcome: str) -> None:
        """A person's outcome for the goal waiting for one (the Figure 6 answer)."""
        if outcome not in OUTCOMES:
            raise ValueError(f"outcome must be one of {', '.join(OUTCOMES)}, not {outcome!r}")
        if self.state != "waiting_for_outcome" or self.active is None:
            raise ValueError(f"no goal is waiting for an outcome (the rehearsal is {self.state})")
        self.state = "running"
        self.choices.append({"t": round(self.time_s, 3), "goal": self.active.goal.id,
                             "outcome": outcome})
        self._end_goal(self.active, outcome, "chosen by the person rehearsing")

    def end_goal(self, outcome: str, reason: str) -> None:
        """End the current goal with an outcome decided outside this vehicle's simulation
        (a team's shared meeting outcome, rehearse/team.py); not a person's input, so not
        among `choices`. ValueError when no goal runs."""
        if outcome not in OUTCOMES:
            raise ValueError(f"outcome must be one of {', '.join(OUTCOMES)}, not {outcome!r}")
        if self.state == "finished" or self.active is None:
            raise ValueError(f"no goal is running (the rehearsal is {self.state})")
        self.state = "running"
        self._end_goal(self.active, outcome, reason)

    def inject(self, fault: str | FaultSpec) -> str:
        """Apply, queue or schedule the fault; the text says which. Refused (ValueError) when
        the rehearsal has finished or the fault is already active or queued."""
        spec = fault if isinstance(fault, FaultSpec) else FaultSpec.parse(fault)
        words = FAULT_WORDS.get(spec.name, spec.name)
        if self.state == "finished":
            raise ValueError(f"the rehearsal has finished: {words} was not injected")
        if spec.at_goal is not None or spec.at_s is not None:
            self.pending_faults.append(spec)
            return f"Fault scheduled: {spec}."
        if spec.name not in REPEATABLE_FAULTS and (
            spec.name in self.active_faults or spec.name in self.queued_faults
        ):
            where = "queued" if spec.name in self.queued_faults else "active"
            raise ValueError(f"{words} is already {where}")
        if self.state == "waiting_for_outcome" and self.active is not None:
            # The goal's plan is over and it waits for a person: a fault cannot change how it
            # ended, so it is kept for the goal that follows.
            self.queued_faults.append(spec.name)
            text = (f"Fault queued: {words} applies when the next goal starts "
                    f"({self.active.goal.id} is waiting for its outcome).")
            self._emit("fault_queued", text, self.active.goal.id, {"fault": spec.name})
            return text
        self._activate(spec.name)
        return f"Fault injected: {words}."

    def values(self, lookahead_s: float = 0.0,
               needed: frozenset[str] | None = None) -> dict[str, float | bool | str]:
        """The quantities the constraint monitors read, now or extrapolated `lookahead_s`
        ahead along the current velocities (vehicle and contacts). Only `needed` quantities
        are computed when given: this runs every few simulated seconds."""
        v = self.vehicle
        t = self.time_s + lookahead_s
        x, y = v.x + v.vx * lookahead_s, v.y + v.vy * lookahead_s
        # Depth changes toward the waypoint's depth and stops there: extrapolating the dive
        # rate past it would report violations the plan never makes.
        change = min(abs(v.vz) * lookahead_s, abs(v.target_depth - v.depth))
        depth = max(0.0, v.depth + math.copysign(change, v.target_depth - v.depth))
        remaining = self.energy_remaining_wh
        leak = "leak" in self.active_faults
        want = needed if needed is not None else ALL_QUANTITIES
        out: dict[str, float | bool | str] = {
            "depth_m": depth,
            "speed_mps": math.hypot(v.vx, v.vy),
            "nav_error_m": v.nav_error_m,
            "energy_wh": self.energy_used_wh,
            "energy_remaining_wh": remaining,
            "duration_s": t,
            "elapsed_s": t,
            "battery_pct": 100.0 * remaining / self.capacity_wh,
            "battery_reserve_pct": 100.0 * max(0.0, remaining - self._reserve_wh())
            / self.capacity_wh,
            "contact_detection_range_m": self.detection_range_m,
            "comms_ok": depth < 0.5 or v.usbl_now,
            "gps_fix": v.gps_now,
            "surfaced": depth < 0.5,
            "safety_equipment_ok": not leak,
            "mission_systems_ok": not leak,
            "heading_deg": math.degrees(v.heading) % 360.0,
        }
        if "altitude_m" in want:
            out["altitude_m"] = max(0.0, self.world.seafloor_depth(x, y) - depth)
        if "latitude_deg" in want or "longitude_deg" in want:
            out["latitude_deg"], out["longitude_deg"] = self.world.to_latlon((x, y))
        if "lane_distance_m" in want:
            out["lane_distance_m"] = self.world.lane_distance((x, y))
        if "contact_distance_m" in want or "contact_range_m" in want:
            contact = self.world.contact_distance((x, y), t)
            out["contact_distance_m"] = out["contact_range_m"] = contact
        if "contact_count" in want:
            out["contact_count"] = float(sum(1 for c in self.world.contacts if c.start_s <= t))
        if "base_distance_m" in want:
            out["base_distance_m"] = math.dist((x, y), self.world.recovery)
        if "current_mps" in want:
            out["current_mps"] = self._current_mps()
        return out

    def observations(self, planned_action: str | None = None) -> dict[str, bool]:
        """What the vehicle observes, in the words default theories use (seed 004 and the
        shipped examples); the contingency layer passes on only what a theory declares."""
        v = self.vehicle
        t = self.time_s
        remaining = self.energy_remaining_wh
        leak = "leak" in self.active_faults
        contact_close = self.world.contact_distance(v.xy, t) < CONTACT_CLOSE_M
        low = remaining <= self._reserve_wh() + self._home_wh()
        usbl_now = t - v.last_usbl_s <= 2 * USBL_PERIOD_S
        floor = self.world.seafloor_depth(v.x, v.y)
        budget = self.orders.target_vehicle()
        time_limit = budget.budget.duration_s if budget and budget.budget else None
        obs = {
            "gps_captured": v.gps_now,
            "usbl_captured": usbl_now,
            "gps_was_captured": t - v.last_gps_s <= FIX_MEMORY_S,
            "usbl_was_captured": t - v.last_usbl_s <= FIX_MEMORY_S,
            "on_surface": v.depth < 0.5,
            "localisation_precision_low": v.nav_error_m > LOCALISATION_PRECISION_M,
            "nav_error_high": v.nav_error_m > NAV_ERROR_HIGH_M,
            "leak": leak,
            "safety_sensor_failure(leak)": leak,
            "mission_system_failure": False,
            "camera_fault": False,
            "low_energy": low,
            "battery_low": low,
            "battery_critical": remaining <= self._reserve_wh() * 0.5,
            "altitude_low": floor - v.depth < ALTITUDE_LOW_M,
            "contact_close": contact_close,
            "surface_contact_close": contact_close,
            "contact_within_1000m": contact_close,
            "mission_time_over": time_limit is not None and t > time_limit,
        }
        for area_id, area in self.world.areas.items():
            if contains(area.polygon, v.xy):
                obs[f"at({area_id.lower()})"] = True
        for area_id in self._transect_areas:
            obs[f"transect_done({area_id.lower()})"] = area_id in self._transects_done
        if planned_action is not None and self.active is not None:
            obs[f"enough_energy({planned_action})"] = self._energy_choice(self.active) is None
        return obs

    # ------------------------------------------------------------------------------ runs

    def _start_run(self) -> None:
        path_index = self.source.begin_run(len(self.runs))
        if path_index is None and self.runs:
            self._finish(None)
            return
        self.runs.append(Run(path_index=path_index))
        if len(self.runs) > 1:
            # A tour starts every path from the same launch with a full battery.
            self.vehicle = Vehicle(*self._launch_point(), last_gps_s=self.time_s)
            self.energy_used_wh = self.expected_used_wh = 0.0
            # Every path of a tour meets the same faults given at the start.
            self.active_faults.clear()
            self.pending_faults = list(self._initial_faults)
            self._transects_done.clear()
            self.trail.clear()
            self._emit("run", f"Path {path_index}: start", data={"path_index": path_index})
        start = self.orders.start if isinstance(self.orders.start, str) else None
        if start is None or start not in self.goals:
            self._emit("error", "The orders name no start goal that exists (M1).")
            self._finish("no start goal")
            return
        # Launch: the vehicle dives at the launch point to the first goal's depth before the
        # mission starts, as it surfaces after the terminal: neither is inside a goal, so no
        # goal's constraints judge them.
        self.vehicle.depth = self.vehicle.target_depth = self._operating_depth(self.goals[start])
        self._start_goal(start)

    def _launch_point(self) -> Point:
        """Where the start goal starts (the verifier's place): the orders sign no launch
        transit and the verifier charges none. Without a place, the recovery point."""
        start = self.orders.start if isinstance(self.orders.start, str) else None
        place = self.world.places.get(start) if start else None
        return place.start if place is not None else self.world.recovery

    def _finish(self, why: str | None) -> None:
        self.active = None
        self.state = "finished"
        if self.queued_faults:
            names = ", ".join(FAULT_WORDS.get(f, f) for f in self.queued_faults)
            self._emit("warning", f"Queued faults not applied, the rehearsal ended: {names}.")
            self.queued_faults.clear()
        if why:
            self._emit("finished", f"Rehearsal ended: {why}.")

    # ------------------------------------------------------------------------------ goals

    def _start_goal(self, goal_id: str) -> None:
        run = self.run
        if len(run.goals) >= self.limits.max_goal_visits:
            self._emit("error", f"More than {self.limits.max_goal_visits} goals on one run: "
                       "the orders loop (G7).")
            self._end_run(None)
            return
        goal = self.goals[goal_id]
        run.goals.append(goal_id)
        facts = facts_of(goal, self.orders)
        waypoints = self._plan(goal)
        leg_m = sum(w.geo_m for w in waypoints if w.kind == "leg")
        work_m = sum(w.geo_m for w in waypoints if w.kind != "leg")
        speed, rate, hold_w = self._priced_work(goal, waypoints, work_m)
        holds = sum(w.hold_s for w in waypoints)
        planned_s = leg_m / self.speed + work_m / speed + holds
        expected = rate * work_m + self.leg_rate_wh_per_m * leg_m + hold_w * holds / 3600.0
        self._priced_m += leg_m + work_m
        self._priced_wh += rate * work_m + self.leg_rate_wh_per_m * leg_m
        active = ActiveGoal(goal, facts, waypoints, planned_s, rate, hold_w, self.time_s,
                            expected_wh=expected, speed=speed)
        active.scripted = self.source.scripted(goal_id, len(run.goals) - 1)
        # Seed 001: a strong opposing current with a 20% chance during each goal, for an
        # uncertain part of it; a disturbance only the simulating source meets.
        if self.source.disturbed and self.rng.random() < STRONG_CURRENT_CHANCE \
                and planned_s > 0:
            begin = self.time_s + self.rng.uniform(0.0, 0.5) * planned_s
            until = begin + self.rng.uniform(0.3, 1.0) * planned_s
            active.strong_current = (begin, until)
        self.active = active
        self._emit("goal", f"Commence: {goal.label.rstrip('.')}.", goal_id,
                   {"behavior": goal.behavior, "area": goal.area,
                    "planned_s": round(planned_s, 1), "expected_wh": round(expected, 3)})
        for spec in list(self.pending_faults):
            if spec.at_goal == goal_id:
                self.pending_faults.remove(spec)
                self._activate(spec.name)
        queued, self.queued_faults = self.queued_faults, []
        for name in queued:
            self._activate(name)

    def _priced_work(self, goal: Goal, waypoints: list[Waypoint], work_m: float
                     ) -> tuple[float, float, float]:
        """(speed, Wh per metre, hold watts) of the goal's own work, from the verifier's cost
        of the goal (verify/costs.goal_cost): its duration bounds the work's time (holds
        shortened and the work sped up in proportion when the plan at cruise would take
        longer), its energy is spread over the work in proportion to time. Without a cost
        the vehicle's profile prices it (cruise power moving, 40% of it holding)."""
        vehicle = self.orders.target_vehicle()
        areas = self.orders.area_index()
        duration, _ = goal_cost(goal, "duration_s", vehicle, areas)
        energy, _ = goal_cost(goal, "energy_wh", vehicle, areas)
        holds = sum(w.hold_s for w in waypoints)
        cruise_s = work_m / self.speed + holds
        factor = 1.0
        if duration is not None and cruise_s > duration:
            factor = duration / cruise_s  # 0 when the goal is said to take no time
            for w in waypoints:
                w.hold_s *= factor
        speed = self.speed / factor if factor > 1e-9 else math.inf
        if energy is None:
            return speed, self.leg_rate_wh_per_m, self.power_w * 0.4
        work_s = work_m / speed if math.isfinite(speed) else 0.0
        total_s = work_s + holds * factor
        if total_s <= 0.0:
            return speed, 0.0, 0.0  # no work to charge (a station goal with no hold)
        rate = energy * work_s / total_s / work_m if work_m > 0 else 0.0
        hold_w = energy * 3600.0 / total_s
        return speed, rate, hold_w

    def _end_goal(self, active: ActiveGoal, outcome: str, reason: str) -> None:
        goal = active.goal
        self.run.outcomes.append(outcome)
        if outcome == "succeed" and goal.area in self._transect_areas \
                and (goal.behavior or "").lower() == "transect":
            self._transects_done.add(goal.area)
        v = self.vehicle
        self._emit("outcome", f"{goal.label}: {outcome} ({reason}).", goal.id,
                   {"outcome": outcome, "reason": reason,
                    "position": [round(v.x, 2), round(v.y, 2), round(v.depth, 2)],
                    "energy_wh": round(active.used_wh, 3)})
        self.active = None
        targets = goal.successors(outcome)
        if not targets:
            self._emit("error", f"{goal.id} names no successor for {outcome} (SINK).", goal.id)
            self._end_run(None)
            return
        if len(targets) > 1:
            self._emit("warning", f"{goal.id} names {len(targets)} successors for {outcome} "
                       f"(G5); following {targets[0]}.", goal.id)
        target = targets[0]
        if target in self.goals:
            self._start_goal(target)
        elif target in self.terminals:
            self._end_run(target)
        else:
            self._emit("error", f"{goal.id} {outcome} names {target}, which is neither a goal "
                       "nor a terminal (G3).", goal.id)
            self._end_run(None)

    def _end_run(self, terminal: str | None) -> None:
        run = self.run
        run.terminal = terminal
        kind = self.terminals[terminal].kind if terminal in self.terminals else None
        run.terminal_kind = kind
        if kind is not None:
            self._emit("terminal", "Mission Complete!" if kind == "complete" else "Mission Abort!",
                       data={"terminal": terminal, "kind": kind})
        self.active = None
        self.vehicle.depth = 0.0
        self.vehicle.vx = self.vehicle.vy = self.vehicle.vz = 0.0
        self._start_run()

    # ------------------------------------------------------------------------------ plans

    def _operating_depth(self, goal: Goal) -> float:
        depth = goal.params.get("depth_m")
        if isinstance(depth, int | float) and not isinstance(depth, bool) and depth >= 0:
            wanted = float(depth)
        elif "depth_m" in goal.envelope:
            low, high = goal.envelope["depth_m"]
            wanted = low + 0.3 * (high - low)
        else:
            wanted = DEFAULT_DEPTH_M
        vehicle = self.orders.target_vehicle()
        if vehicle and "depth_m" in vehicle.envelope:
            low, high = vehicle.envelope["depth_m"]
            wanted = min(max(wanted, low), high)
        return max(0.0, min(wanted, self.world.floor_base_m - 25.0))

    def _plan(self, goal: Goal) -> list[Waypoint]:
        depth = self._operating_depth(goal)
        area = self.world.areas.get(goal.area) if goal.area else None
        behavior = (goal.behavior or "").lower()
        recovery = behavior in RECOVERY_BEHAVIORS or (
            area is not None and area.centre == self.world.recovery
        )
        # A recovery goal ends at the recovery point; surfacing for pick-up follows the
        # terminal, outside every goal's constraints (C7 of the exemplar holds until then).
        if self.vehicle.forced_surface:
            depth = 0.0
        if area is None:
            hold = float(goal.params.get("duration_s", 60.0) or 60.0)
            x, y = self.world.recovery if recovery else self.vehicle.xy
            return [Waypoint(x, y, 0.0 if recovery else depth, min(hold, 3_600.0), "hold")]
        # Where the goal runs is the verifier's place (verify/legs.py): its sweep or its
        # station, so the leg flown into it is the leg that was checked.
        place = self.world.places.get(goal.id)
        points: list[Waypoint] = []
        if place is not None and place.track is not None:
            kind = "transect" if behavior == "transect" else "search"
            points = [Waypoint(float(x), float(y), depth, 0.0, kind)
                      for x, y in place.track.coords]
        else:
            cx, cy = place.start if place is not None else area.centre
            if behavior in HOLD_BEHAVIORS:
                hold = goal.params.get("duration_s", HOLD_BEHAVIORS[behavior])
                hold_s = float(hold) if isinstance(hold, int | float) and hold >= 0 else \
                    HOLD_BEHAVIORS[behavior]
                points = [Waypoint(cx, cy, depth, min(hold_s, 6 * 3_600.0), behavior)]
            else:
                points = [Waypoint(cx, cy, depth, 0.0, "transit")]
        if self.vehicle.forced_surface:
            for p in points:
                p.depth = 0.0
        first = points[0]
        if math.dist(self.vehicle.xy, (first.x, first.y)) > 1.0:
            points = [Waypoint(first.x, first.y, first.depth, 0.0, "leg"), *points]
        return self._measured(points)

    def _measured(self, points: list[Waypoint]) -> list[Waypoint]:
        """Each segment's geodesic length (one projection call per plan): the vehicle flies
        the frame's straight line but counts metres on the ellipsoid, as the legs do."""
        xs = [self.vehicle.x, *(p.x for p in points)]
        ys = [self.vehicle.y, *(p.y for p in points)]
        lats, lons = self.world.frame.to_latlon(xs, ys)
        _, _, metres = GEOD.inv(lons[:-1], lats[:-1], lons[1:], lats[1:])
        for k, p in enumerate(points):
            planar = math.dist((xs[k], ys[k]), (xs[k + 1], ys[k + 1]))
            p.geo_m = float(metres[k]) if planar > 1e-9 else 0.0
            p.scale = p.geo_m / planar if planar > 1e-9 else 1.0
        return points

    # ------------------------------------------------------------------------------ physics

    def _current_factor(self) -> float:
        active = self.active
        if active and active.strong_current:
            begin, until = active.strong_current
            if begin <= self.time_s < until:
                return STRONG_CURRENT_FACTOR
        return 1.0

    def _current_mps(self) -> float:
        return STRONG_CURRENT_MPS if self._current_factor() > 1.0 else NORMAL_CURRENT_MPS

    def _move(self, active: ActiveGoal, dt: float) -> float:
        """One step of the plan. The step's time is spent waypoint after waypoint: time left
        when a waypoint is reached carries on to the next one (or its hold), so that a plan
        takes the time its metres and holds take, not a step more per waypoint. Returns the
        part of the step left over when the plan was done within it."""
        v = self.vehicle
        strong = self._current_factor() > 1.0
        if strong != self._strong_current:
            self._strong_current = strong
            self._emit("current", "Strong opposing current: consumption doubled (seed 001)."
                       if strong else "The strong current has passed.", active.goal.id,
                       {"strong": strong})
        if active.finished_plan:
            v.vx = v.vy = v.vz = 0.0
            return 0.0
        factor = self._current_factor()
        target = 0.0 if v.forced_surface else active.waypoints[active.index].depth
        v.target_depth = target
        dz = target - v.depth
        rise = max(-DIVE_RATE_MPS * dt, min(DIVE_RATE_MPS * dt, dz))
        v.depth = max(0.0, v.depth + rise)
        v.vz = rise / dt
        x0, y0 = v.x, v.y
        energy = 0.0
        left = dt
        while left > 1e-9 and not active.finished_plan:
            w = active.waypoints[active.index]
            dx, dy = w.x - v.x, w.y - v.y
            distance = math.hypot(dx, dy)
            speed = self.speed if w.kind == "leg" else active.speed
            if distance > 1e-6:
                to_go_m = distance * w.scale  # geodesic metres
                moved_m = min(speed * left, to_go_m)
                arrived = moved_m >= to_go_m
                v.heading = math.atan2(dy, dx)
                if arrived:
                    v.x, v.y = w.x, w.y
                else:
                    moved = moved_m / w.scale
                    v.x += dx / distance * moved
                    v.y += dy / distance * moved
                left -= moved_m / speed if math.isfinite(speed) else 0.0
                active.done_s += moved_m / speed
                rate = self.leg_rate_wh_per_m if w.kind == "leg" else active.rate_wh_per_m
                energy += moved_m * rate * factor
                self.expected_used_wh += moved_m * rate
                if w.kind == "leg":
                    active.leg_m += moved_m
                if not arrived:
                    break
            # Depth changes while the vehicle moves and holds, and never holds the plan up:
            # the verifier's costs charge metres and holds, no time for diving.
            if w.kind == "leg" and active.held_s == 0.0:
                self._leg_flown(active, w)
            if active.held_s < w.hold_s:
                # A hold is charged for the part held, not the whole step.
                held = min(left, w.hold_s - active.held_s)
                active.held_s += held
                active.done_s += held
                left -= held
                hold_energy = active.hold_w * held / 3600.0
                energy += hold_energy * factor
                self.expected_used_wh += hold_energy
            if active.held_s < w.hold_s:
                break
            active.index += 1
            active.held_s = 0.0
        unused = left if active.finished_plan and left > 1e-9 else 0.0
        spent = dt - unused
        v.vx, v.vy = ((v.x - x0) / spent, (v.y - y0) / spent) if spent > 1e-9 else (0.0, 0.0)
        active.used_wh += energy
        self.energy_used_wh += energy
        if not self.trail or math.dist(self.trail[-1][:2], v.xy) >= 25.0 \
                or abs(self.trail[-1][2] - v.depth) >= 2.0:
            self.trail.append((v.x, v.y, v.depth))
        return unused

    def _leg_flown(self, active: ActiveGoal, w: Waypoint) -> None:
        run = self.run
        if len(run.goals) < 2 or len(self.flown_legs) >= self.limits.max_events:
            return  # the launch is no leg between goals
        self.flown_legs.append({"from": run.goals[-2], "outcome": run.outcomes[-1],
                                "to": active.goal.id, "length_m": round(active.leg_m, 6),
                                "planned_m": round(w.geo_m, 6)})

    def _navigate(self, dt: float) -> None:
        v = self.vehicle
        t = self.time_s
        drift = FAULT_DRIFT_PER_M if "nav_drift" in self.active_faults else NAV_DRIFT_PER_M
        v.nav_error_m += drift * math.hypot(v.vx, v.vy) * dt
        v.gps_now = v.depth < 0.5 and "gps_loss" not in self.active_faults
        if v.gps_now:
            v.last_gps_s = t
            v.nav_error_m = min(v.nav_error_m, GPS_FIX_ERROR_M)
        # The acoustic (USBL) fix from the support vessel arrives periodically within range;
        # navigation drift is modelled as the loss of that link plus a faster drift.
        v.usbl_now = False
        if (
            "nav_drift" not in self.active_faults
            and math.dist(v.xy, self.world.recovery) <= USBL_RANGE_M
            and t - v.last_usbl_s >= USBL_PERIOD_S
            and v.depth >= 0.5
        ):
            v.usbl_now = True
            v.last_usbl_s = t
            v.nav_error_m = min(v.nav_error_m, USBL_FIX_ERROR_M)

    # ------------------------------------------------------------------------------ judging

    def _judge(self, active: ActiveGoal) -> None:
        if self.time_s >= self._next_check_s or active.finished_plan:
            self._next_check_s = self.time_s + CHECK_PERIOD_S
            if self._check(active):
                return
        # 4. The plan.
        if active.finished_plan:
            self._propose(active, "succeed", "the plan is complete", {}, plan_done=True)
        elif self.time_s - active.started_s > self.limits.max_goal_s:
            self._propose(active, "fail", "the goal ran out of time", {}, plan_done=True)
        elif active.scripted and active.scripted != "succeed" \
                and active.progress >= SCRIPTED_CUT[active.scripted]:
            self._end_goal(active, active.scripted, "replayed from the traversal")

    def _check(self, active: ActiveGoal) -> bool:
        """Rules, monitors and energy; True when the goal ended or now waits."""
        goal_id = active.goal.id
        # 1. Default rules: the extension of the theory under what the vehicle observes.
        if self.contingency.active:
            action = self.contingency.planned_action(active.goal, self.contingency_actions)
            verdict = self.contingency.check(self.observations(action), action)
            assert verdict is not None
            for rule in verdict.fired_new:
                self.rule_firings[rule] = self.rule_firings.get(rule, 0) + 1
            if verdict.fired_new:
                self._emit("rules", "Rules fired: " + ", ".join(verdict.fired_new) + ".",
                           goal_id, {"fired": list(verdict.fired_new)})
            if verdict.refused and self._obey(active, action, verdict):
                return True
        # 2. Constraint monitors, now and a little ahead.
        now = self.values(needed=self.needed)
        ahead = self.values(IMMINENT_S, needed=self.needed)
        for monitor in self.monitors:
            if not monitor.applies(goal_id):
                continue
            if monitor.holds(now, active.facts) is False or \
                    monitor.holds(ahead, active.facts) is False:
                reason = f"{monitor.constraint_id} would be violated: {monitor.expr}"
                if self._propose(active, "violate", reason,
                                 {"constraint": monitor.constraint_id,
                                  "values": _read_values(monitor, now)}):
                    return True
                break
        # 3. Energy (seed 001): give up a goal that can no longer be finished with the reserve
        # to reach recovery, at the consumption actually measured so far.
        if self.time_s - active.last_energy_check >= ENERGY_CHECK_S:
            active.last_energy_check = self.time_s
            give_up = self._energy_choice(active)
            if give_up is not None and self._propose(active, "fail", give_up[0], give_up[1]):
                return True
        return self.energy_remaining_wh <= 0.0 and self._propose(
            active, "fail", "the battery is empty", {}
        )

    def _obey(self, active: ActiveGoal, action: str, verdict: RuleVerdict) -> bool:
        """A refused planned action: obey the safe action. A change of depth on the way home
        keeps the goal; anything else ends it (fail when the goal was dropped, violate for a
        safety action). True when the goal ended or now waits."""
        safe = verdict.safe_action
        v = self.vehicle
        homeward = self._is_recovery(active.goal)
        if safe in POSTURE_ACTIONS and homeward:
            if safe == "surface" and not v.forced_surface:
                v.forced_surface = True
                self._emit("safe_action", f"Safety action: surface ({verdict.reason})",
                           active.goal.id, {"action": safe, "rules": list(verdict.because)})
            return False
        if safe in ("surface", "shutdown", "shut_down"):
            v.forced_surface = True
        data = {"planned": action, "action": safe, "rules": list(verdict.because),
                "explanation": verdict.reason}
        text = (f"rules refuse {action}" + (f" and require {safe}" if safe else "")
                + f": {verdict.reason}")
        return self._propose(active, verdict.outcome, text, data)

    def _is_recovery(self, goal: Goal) -> bool:
        behavior = (goal.behavior or "").lower()
        area = self.world.areas.get(goal.area or "")
        return behavior in RECOVERY_BEHAVIORS or bool(area and area.centre == self.world.recovery)

    def _propose(self, active: ActiveGoal, outcome: str, reason: str, data: dict[str, Any],
                 *, plan_done: bool = False) -> bool:
        """The simulation's view of how the goal ends; the source decides. True when the goal
        ended or now waits."""
        decision = self.source.decide(outcome, plan_done=plan_done, scripted=active.scripted)
        if decision == "end":
            self._emit("decision", reason, active.goal.id, {"outcome": outcome, **data})
            self._end_goal(active, outcome, reason)
            return True
        if decision == "scripted" and active.scripted:
            self._end_goal(active, active.scripted, "replayed from the traversal")
            return True
        if decision == "wait":
            self.state = "waiting_for_outcome"
            suggestion = active.suggestion or (outcome, reason)
            self._emit("waiting", QUESTION,
                       active.goal.id, {"suggested": suggestion[0], "because": suggestion[1]})
            return True
        if active.suggestion is None and not plan_done:
            # Manual and scripted sources keep going; remember what the simulation saw.
            active.suggestion = (outcome, reason)
            self._emit("observed", reason, active.goal.id, {"outcome": outcome, **data})
        return False

    def _reserve_wh(self) -> float:
        return RESERVE_FRACTION * self.capacity_wh

    def _learned_factor(self) -> float:
        """Seed 001's linear model: measured over expected consumption so far."""
        if self.expected_used_wh < 1e-6:
            return 1.0
        return max(0.5, min(4.0, self.energy_used_wh / self.expected_used_wh))

    def _transit_rate(self) -> float:
        if self._priced_m < 100.0:
            return self.power_w / self.speed / 3600.0
        return self._priced_wh / self._priced_m

    def _home_wh(self) -> float:
        distance = math.dist(self.vehicle.xy, self.world.recovery)
        return distance * self._transit_rate() * self._learned_factor()

    def _energy_choice(self, active: ActiveGoal) -> tuple[str, dict[str, Any]] | None:
        if self._is_recovery(active.goal):
            return None  # going home is never given up for energy
        factor = self._learned_factor()
        rest = self._remaining_plan_m(active) * active.rate_wh_per_m * factor
        home = self._home_after(active) * self._transit_rate() * factor
        needed = rest + home + self._reserve_wh()
        remaining = self.energy_remaining_wh
        if remaining >= needed:
            return None
        data = {"remaining_wh": round(remaining, 3), "goal_rest_wh": round(rest, 3),
                "home_wh": round(home, 3), "reserve_wh": round(self._reserve_wh(), 3),
                "consumption_factor": round(factor, 3)}
        home_and_reserve = home + self._reserve_wh()
        return (f"energy: {remaining:.0f} Wh left cannot cover the rest of the goal "
                f"({rest:.0f} Wh) and the way home with the reserve ({home_and_reserve:.0f}"
                " Wh); goal given up", data)

    def _remaining_plan_m(self, active: ActiveGoal) -> float:
        x, y = self.vehicle.xy
        total = 0.0
        for w in active.waypoints[active.index:]:
            total += math.dist((x, y), (w.x, w.y))
            x, y = w.x, w.y
        return total

    def _home_after(self, active: ActiveGoal) -> float:
        if not active.waypoints:
            return math.dist(self.vehicle.xy, self.world.recovery)
        last = active.waypoints[-1]
        return math.dist((last.x, last.y), self.world.recovery)

    # ------------------------------------------------------------------------------ faults

    def _scheduled_faults(self, *, after_step: bool = False) -> None:
        """Faults due now. A fault timed at T takes effect after the step that reaches T
        (as one injected live between steps at T does, so a recorded `name@T` reproduces
        the live run); one due earlier, or untimed, at the start of the step."""
        for spec in list(self.pending_faults):
            due = spec.at_s is not None and (
                self.time_s >= spec.at_s if after_step else self.time_s > spec.at_s)
            if due or (not after_step and spec.at_s is None and spec.at_goal is None):
                self.pending_faults.remove(spec)
                self._activate(spec.name)

    def _activate(self, name: str) -> None:
        self.fault_log.append(f"{name}@{self.time_s:g}")
        v = self.vehicle
        if name == "low_energy":
            # Most of the battery gone at once (a failing cell): what is left is just above
            # the reserve, so the energy check must act.
            target_left = self._reserve_wh() * 1.5
            if self.energy_remaining_wh > target_left:
                self.energy_used_wh = self.capacity_wh - target_left
        elif name == "contact_close":
            contact = self.world.closing_contact(v.xy, v.heading, self.time_s, self.rng)
            if contact is None:
                self._emit("warning", "No more contacts can be added.")
                return
        self.active_faults.add(name)
        self._emit("fault", f"Fault injected: {name.replace('_', ' ')}.", self.current_goal,
                   {"fault": name})

    # ------------------------------------------------------------------------------ events

    def _emit(self, kind: str, text: str, goal: str | None = None,
              data: dict[str, Any] | None = None) -> None:
        event = Event(round(self.time_s, 3), kind, text, goal, data or {})
        if len(self.events) < self.limits.max_events:
            self.events.append(event)
        else:
            self.events_dropped += 1
        for listener in self.listeners:
            listener(event)


def _read_values(monitor: Monitor, values: dict[str, float | bool | str]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for name in sorted(identifiers(monitor.expr)):
        if name in values:
            value = values[name]
            out[name] = round(value, 3) if isinstance(value, float) and value < FAR_M else value
    return out
