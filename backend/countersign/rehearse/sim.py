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
verifier's figure for a path bounds what a nominal rehearsal of that path uses:
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

import random
from collections.abc import Callable, Sequence
from typing import Any

from ..orders.model import OUTCOMES, Area, Orders
from ..orders.model import Vehicle as OrdersVehicle
from ..verify.expressions import identifiers
from ..verify.nesting import Nesting
from ..verify.paths import INDENT
from .contingency import Contingency
from .geo import Point
from .monitor import facts_of, monitors_of
from .sim_energy import reserve_wh
from .sim_judge import judge
from .sim_model import (
    DEFAULT_CAPACITY_WH,
    DEFAULT_POWER_W,
    DEFAULT_SPEED_MPS,
    FAULT_WORDS,
    FAULTS,
    QUESTION,
    REPEATABLE_FAULTS,
    STRONG_CURRENT_CHANCE,
    ActiveGoal,
    Event,
    FaultSpec,
    Limits,
    Run,
    State,
    Vehicle,
)
from .sim_motion import move, navigate
from .sim_nesting import enter, fault_names, leave, rehearsed_form, status
from .sim_plans import operating_depth, plan, priced_work
from .sim_sensing import observations, values
from .sources import OutcomeSource
from .world import World

__all__ = ["FAULTS", "QUESTION", "Event", "FaultSpec", "Limits", "Run", "Simulation"]


class Simulation:
    """One rehearsal's state, its public controls (`advance`, `step`, `choose`, `inject`) and
    its runs and goals (start, end, successors, faults, events). The rest of each step is done
    by the modules beside it, which read and update this state: `sim_plans` (a goal's
    waypoints and priced work), `sim_motion` (moving, charging energy, navigating),
    `sim_judge` (rules, monitors, energy and the plan proposing an outcome), `sim_energy`
    (the way home) and `sim_sensing` (the values monitors and rules read)."""

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
        flown: tuple[Orders, Nesting | None] | None = None,
    ) -> None:
        # A refined mission is flown as its flat automaton (sim_nesting.py); `nesting` says
        # where each of its goals sits in the hierarchy. `flown` is that form made already
        # (a campaign makes it once for thousands of simulations).
        orders, self.nesting = flown if flown is not None else rehearsed_form(orders)
        self.inside: list[str] = []  # the refined goals begun and not ended on this run
        self.timeouts: list[dict[str, Any]] = []  # time-outs that ended a refinement
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
        self._take_profile(orders.target_vehicle())
        self._initial_faults: tuple[FaultSpec, ...] = tuple(
            f if isinstance(f, FaultSpec) else FaultSpec.parse(f) for f in faults
        )
        self._begin_record(orders)
        self.vehicle = Vehicle(*self._launch_point())
        self.trail: list[tuple[float, float, float]] = []
        # The legs flown between goals: from, outcome, to and geodesic metres.
        self.flown_legs: list[dict[str, Any]] = []
        self.leg_rate_wh_per_m = self.power_w / self.speed / 3600.0  # verify/costs' leg cost
        # Per-metre rates of the goals run so far: the price of the way home (seed 001 plans
        # with the consumption it has learnt, not with a catalogue figure).
        self._priced_m = 0.0
        self._priced_wh = 0.0
        self.listeners: list[Callable[[Event], None]] = []
        self._start_run()

    def _take_profile(self, vehicle: OrdersVehicle | None) -> None:
        """Speed, power, energy and contact range from the performing vehicle's profile (the
        defaults where it gives none)."""
        self.speed = vehicle.speed_mps if vehicle and vehicle.speed_mps else DEFAULT_SPEED_MPS
        self.power_w = vehicle.power_w if vehicle and vehicle.power_w else DEFAULT_POWER_W
        budget = vehicle.budget.energy_wh if vehicle and vehicle.budget else None
        self.capacity_wh = float(budget) if budget else DEFAULT_CAPACITY_WH
        self.detection_range_m = 6_000.0
        if vehicle and "contact_detection_range_m" in vehicle.envelope:
            self.detection_range_m = float(vehicle.envelope["contact_detection_range_m"][1])

    def _begin_record(self, orders: Orders) -> None:
        """What a run records and counts, empty at its start."""
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
        unused = move(self, active, dt)
        if unused > 0.0:
            self.time_s -= unused
            dt -= unused
        navigate(self, dt)
        judge(self, active)
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

    def refined_status(self) -> dict[str, Any]:
        """The breadcrumb and last time-out of a refined mission (`sim_nesting.status`)."""
        return status(self)

    def values(self, lookahead_s: float = 0.0,
               needed: frozenset[str] | None = None) -> dict[str, float | bool | str]:
        """The quantities the constraint monitors read (`sim_sensing.values`)."""
        return values(self, lookahead_s, needed)

    def observations(self, planned_action: str | None = None) -> dict[str, bool]:
        """What the vehicle observes, in the words of default theories
        (`sim_sensing.observations`)."""
        return observations(self, planned_action)

    # ------------------------------------------------------------------------------ runs

    def _start_run(self) -> None:
        path_index = self.source.begin_run(len(self.runs))
        if path_index is None and self.runs:
            self._finish(None)
            return
        self.runs.append(Run(path_index=path_index))
        self.inside.clear()
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
        self.vehicle.depth = self.vehicle.target_depth = operating_depth(self, self.goals[start])
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
        waypoints = plan(self, goal)
        leg_m = sum(w.geo_m for w in waypoints if w.kind == "leg")
        work_m = sum(w.geo_m for w in waypoints if w.kind != "leg")
        speed, rate, hold_w = priced_work(self, goal, waypoints, work_m)
        holds = sum(w.hold_s for w in waypoints)
        planned_s = leg_m / self.speed + work_m / speed + holds
        expected = rate * work_m + self.leg_rate_wh_per_m * leg_m + hold_w * holds / 3600.0
        self._priced_m += leg_m + work_m
        self._priced_wh += rate * work_m + self.leg_rate_wh_per_m * leg_m
        active = ActiveGoal(goal, facts, waypoints, planned_s, rate, hold_w, self.time_s,
                            speed=speed)
        active.scripted = self.source.scripted(goal_id, len(run.goals) - 1)
        # Seed 001: a strong opposing current with a 20% chance during each goal, for an
        # uncertain part of it; a disturbance only the simulating source meets.
        if self.source.disturbed and self.rng.random() < STRONG_CURRENT_CHANCE \
                and planned_s > 0:
            begin = self.time_s + self.rng.uniform(0.0, 0.5) * planned_s
            until = begin + self.rng.uniform(0.3, 1.0) * planned_s
            active.strong_current = (begin, until)
        self.active = active
        depth = enter(self, goal_id)
        data: dict[str, Any] = {"behavior": goal.behavior, "area": goal.area,
                                "planned_s": round(planned_s, 1),
                                "expected_wh": round(expected, 3)}
        if self.nesting is not None:
            data["depth"] = depth
        self._emit("goal", f"{INDENT * depth}Commence: {goal.label.rstrip('.')}.", goal_id, data)
        names = fault_names(self.nesting, goal_id)
        for spec in list(self.pending_faults):
            if spec.at_goal in names:
                self.pending_faults.remove(spec)
                self._activate(spec.name)
        queued, self.queued_faults = self.queued_faults, []
        for name in queued:
            self._activate(name)

    def _end_goal(self, active: ActiveGoal, outcome: str, reason: str) -> None:
        goal = active.goal
        self.run.outcomes.append(outcome)
        if outcome == "succeed" and goal.area in self._transect_areas \
                and (goal.behavior or "").lower() == "transect":
            self._transects_done.add(goal.area)
        v = self.vehicle
        data: dict[str, Any] = {"outcome": outcome, "reason": reason,
                                "position": [round(v.x, 2), round(v.y, 2), round(v.depth, 2)],
                                "energy_wh": round(active.used_wh, 3)}
        if self.nesting is not None:
            data["depth"] = len(self.inside)
        self._emit("outcome", f"{goal.label}: {outcome} ({reason}).", goal.id, data)
        self.active = None
        leave(self, goal.id, outcome)
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
            target_left = reserve_wh(self) * 1.5
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
