"""A team's rehearsal: every member's `Simulation` in one world clock.

Orders with a `team` hold one MEA per vehicle; a goal naming `meet: R` in two or more members'
orders is one meeting (DESIGN.md "Refinement and teams"). Each member runs its own
`Simulation` (its own world, profile, budget, faults and outcome source) through the public
API only; this module advances them together, TICK_S simulated seconds at a time, and makes
the meetings joint, as `verify/team.py` defines a joint execution:

- a member at a meeting goal flies there and holds as its plan says, then keeps holding
  (loitering, charged at 40% of cruise power, as the simulation holds) until every member
  whose orders name the meeting stands at it with its plan done;
- the meeting then has one shared outcome, and every member leaves with it, each to its own
  successor for that outcome: the outcome a replayed member's path prescribes (the first such
  member in team order), else the worst outcome any member's simulation saw while it held
  (violate before fail before succeed), else succeed. A member never ends a meeting goal on
  its own;
- a member waiting for a partner that can no longer come ends its wait as the TEAM finding
  describes a deadlock: the partner has ended, has gone past the meeting (no goal naming it is
  reachable from where it is), or waits at another meeting first while nothing can move. The
  event says so in words; the member is left waiting (its run ends in no terminal) and the
  others go on. The joint end is written as `verify.team.JointCounts.key` writes it.

Everything is bounded: each member by its own `Limits`, the team clock by `max_team_s`, the
team's events by `Limits.max_events` (the rest are counted).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

from ..orders.canonical import digest
from ..orders.model import OUTCOMES, Area, Orders, TeamMember
from .sim import Event, FaultSpec, Limits, Simulation
from .sources import Decision, OutcomeSource, make_source

TICK_S = 10.0  # team clock step: meetings are assembled and judged this often
WORST_FIRST = ("violate", "fail", "succeed")
LOITER_POWER_FRACTION = 0.4  # sim.py holds at 40% of cruise power when no cost prices it
MemberState = Literal["running", "waiting", "finished", "deadlocked"]
TEAM_SOURCES = ("simulate", "replay")


class MeetingSource(OutcomeSource):
    """A member's outcome source with meetings taken out of its hands: at a meeting goal it
    never ends the goal (the team does, with the shared outcome); what it would have decided
    is kept as the member's proposal for the meeting."""

    def __init__(self, inner: OutcomeSource, meeting_goals: Mapping[str, str]) -> None:
        self.inner = inner
        self.kind = inner.kind
        self.disturbed = inner.disturbed
        self.meeting_goals = dict(meeting_goals)
        self.current: str | None = None
        self.scripted_meeting: dict[str, str] = {}  # meeting goal -> the path's outcome

    def begin_run(self, run_index: int) -> int | None:
        return self.inner.begin_run(run_index)

    def scripted(self, goal_id: str, position: int) -> str | None:
        self.current = goal_id  # called when each goal starts
        outcome = self.inner.scripted(goal_id, position)
        if goal_id in self.meeting_goals:
            if outcome is not None:
                self.scripted_meeting[goal_id] = outcome
            return None  # no cut short: the meeting's outcome is shared
        return outcome

    def decide(self, outcome: str, *, plan_done: bool, scripted: str | None) -> Decision:
        if self.current in self.meeting_goals:
            return "continue"
        return self.inner.decide(outcome, plan_done=plan_done, scripted=scripted)


@dataclass(frozen=True)
class TeamEvent:
    """A member's simulation event, or a team event (meeting, deadlock), naming its vehicle."""

    vehicle: str
    event: Event

    def to_json(self) -> dict[str, Any]:
        return {"vehicle": self.vehicle, **self.event.to_json()}

    @property
    def line(self) -> str:
        goal = f" {self.event.goal}" if self.event.goal else ""
        return f"{self.vehicle}{goal}: {self.event.text}"


@dataclass
class Member:
    vehicle: str
    orders: Orders
    sim: Simulation
    source: MeetingSource
    meets: dict[str, str]  # goal id -> meeting id
    reach: dict[str, frozenset[str]]  # goal id -> meetings reachable from it (itself included)
    state: MemberState = "running"

    def at_meeting(self) -> str | None:
        """The meeting this member stands at, its plan there done (it holds); else None."""
        active = self.sim.active
        if self.state in ("finished", "deadlocked") or active is None:
            return None
        meet = self.meets.get(active.goal.id)
        return meet if meet is not None and active.finished_plan else None

    def can_still_meet(self, meet: str) -> bool:
        if self.state in ("finished", "deadlocked"):
            return False
        goal = self.sim.current_goal
        return goal is not None and meet in self.reach.get(goal, frozenset())

    @property
    def end(self) -> str | None:
        """Where the member ended: its terminal, or None (left waiting, or still going)."""
        return self.sim.run.terminal if self.state == "finished" else None


@dataclass
class Meeting:
    id: str
    vehicles: tuple[str, ...]
    t: float
    outcome: str
    reason: str
    goals: dict[str, str] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        return {"meet": self.id, "t": round(self.t, 3), "outcome": self.outcome,
                "reason": self.reason, "goals": dict(self.goals)}


def _meetings_reachable(orders: Orders, meets: Mapping[str, str]) -> dict[str, frozenset[str]]:
    """For each goal, the meetings a member there can still reach (its own included)."""
    goals = orders.goal_index()
    reach: dict[str, frozenset[str]] = {}
    visiting: set[str] = set()

    def of(goal_id: str) -> frozenset[str]:
        if goal_id in reach:
            return reach[goal_id]
        if goal_id in visiting or goal_id not in goals:
            return frozenset()  # a loop (G7) or a terminal: nothing more
        visiting.add(goal_id)
        found = {meets[goal_id]} if goal_id in meets else set()
        for outcome in OUTCOMES:
            for target in goals[goal_id].successors(outcome):
                found |= of(target)
        visiting.discard(goal_id)
        reach[goal_id] = frozenset(found)
        return reach[goal_id]

    # Successors first, so each call finds its successors done: no deep recursion.
    for goal_id in _post_order(goals):
        of(goal_id)
    return reach


def _post_order(goals: Mapping[str, Any]) -> list[str]:
    """Goals ordered so that successors come first where the graph allows (no recursion)."""
    order: list[str] = []
    seen: set[str] = set()
    for root in goals:
        if root in seen:
            continue
        stack: list[tuple[str, bool]] = [(root, False)]
        while stack:
            node, done = stack.pop()
            if done:
                order.append(node)
                continue
            if node in seen:
                continue
            seen.add(node)
            stack.append((node, True))
            for outcome in OUTCOMES:
                for target in goals[node].successors(outcome):
                    if target in goals and target not in seen:
                        stack.append((target, False))
    return order


def team_fault_specs(faults: Sequence[str], vehicles: Sequence[str]) -> dict[str, list[str]]:
    """`VEHICLE:FAULT[@WHEN]` for one member, `FAULT[@WHEN]` for every member; ValueError
    naming the fault and the vehicles when it cannot be read."""
    out: dict[str, list[str]] = {v: [] for v in vehicles}
    for text in faults:
        vehicle, sep, spec = text.partition(":")
        if not sep:
            vehicle, spec = "", text
        FaultSpec.parse(spec)
        if vehicle and vehicle not in out:
            raise ValueError(f"fault {text!r} names vehicle {vehicle!r}, which is not in the "
                             f"team ({', '.join(vehicles)})")
        for v in ([vehicle] if vehicle else vehicles):
            out[v].append(spec)
    return out


class TeamSimulation:
    """Every member's simulation in one world clock, meetings joint (see the module)."""

    def __init__(
        self,
        orders: Orders,
        *,
        seed: int = 0,
        source: str = "simulate",
        paths: Mapping[str, int] | None = None,
        faults: Sequence[str] = (),
        limits: Limits | None = None,
        charts: Sequence[Area] = (),
        max_team_s: float | None = None,
    ) -> None:
        if orders.team is None:
            raise ValueError("these orders are one vehicle's, not a team's")
        if source not in TEAM_SOURCES:
            raise ValueError(f"a team is rehearsed with the simulate or replay source (each "
                             f"member's outcomes from its simulation or one path of its own "
                             f"orders), not {source!r}")
        self.orders = orders
        self.limits = limits or Limits()
        self.max_team_s = max_team_s if max_team_s is not None else \
            self.limits.max_steps * self.limits.step_s
        vehicles = [m.vehicle for m in orders.team]
        paths = dict(paths or {})
        unknown = sorted(set(paths) - set(vehicles))
        if unknown:
            raise ValueError(f"paths name {', '.join(unknown)}, not in the team "
                             f"({', '.join(vehicles)})")
        per_vehicle = team_fault_specs(faults, vehicles)
        self.events: list[TeamEvent] = []
        self.events_dropped = 0
        self.meetings: list[Meeting] = []
        self.time_s = 0.0
        self.state: Literal["running", "finished"] = "running"
        self.members: list[Member] = []
        self.participants: dict[str, tuple[str, ...]] = {}
        for index, team_member in enumerate(orders.team):
            kind = "replay" if team_member.vehicle in paths else source
            self._add_member(team_member, kind, path_index=paths.get(team_member.vehicle),
                             seed=seed + index, faults=per_vehicle[team_member.vehicle],
                             charts=charts)
        self._judge_meetings()
        self._maybe_finish()

    def _add_member(self, team_member: TeamMember, kind: str, *, path_index: int | None,
                    seed: int, faults: Sequence[str], charts: Sequence[Area]) -> None:
        """One member's simulation, its outcomes from `kind` with meetings shared, its events
        relayed to the team's."""
        member_orders = team_member.orders
        meets = {g.id: g.meet for g in member_orders.goal_index().values()
                 if g.meet is not None}
        for meet in sorted(set(meets.values())):
            self.participants[meet] = (*self.participants.get(meet, ()), team_member.vehicle)
        try:
            inner = make_source(kind, member_orders, path_index=path_index,
                                max_tour_paths=self.limits.max_tour_paths)
        except ValueError as exc:  # a path out of range: name whose
            raise ValueError(f"member {team_member.vehicle}: {exc}") from None
        wrapped = MeetingSource(inner, meets)
        # Members' worlds differ by seed as the vehicles do: the same team and seed give
        # the same rehearsal.
        sim = Simulation(member_orders, seed=seed, source=wrapped, faults=faults,
                         limits=self.limits, charts=charts)
        member = Member(team_member.vehicle, member_orders, sim, wrapped, meets,
                        _meetings_reachable(member_orders, meets))
        # The first events (launch, first goal) were emitted while constructing.
        for event in sim.events:
            self._add(member.vehicle, event)
        sim.listeners.append(self._listener(member.vehicle))
        self.members.append(member)
        if sim.state == "finished":
            member.state = "finished"

    # ------------------------------------------------------------------------------ public

    @property
    def vehicles(self) -> tuple[str, ...]:
        return tuple(m.vehicle for m in self.members)

    def member(self, vehicle: str) -> Member:
        for member in self.members:
            if member.vehicle == vehicle:
                return member
        raise KeyError(vehicle)

    def advance(self, seconds: float) -> None:
        target = self.time_s + seconds
        while self.state == "running" and self.time_s < target - 1e-9:
            self.step()

    def step(self) -> None:
        """One tick of the team clock: every member moves to the tick's end (a member holding
        at a meeting loiters), then meetings are assembled and waits judged."""
        if self.state != "running":
            return
        if self.time_s >= self.max_team_s:
            self._emit_all("finished", f"Team rehearsal stopped after {self.max_team_s:g} "
                           "simulated seconds (the time bound).")
            self._finish()
            return
        target = min(self.time_s + TICK_S, self.max_team_s)
        for member in self.members:
            if member.state in ("finished", "deadlocked"):
                continue
            sim = member.sim
            before = sim.time_s
            held_at = member.at_meeting()
            if sim.state != "finished":
                sim.advance(target - sim.time_s)
            if held_at is not None:
                self._loiter(member, sim.time_s - before)
            if sim.state == "finished":
                member.state = "finished"
        self.time_s = target
        self._judge_meetings()
        self._maybe_finish()

    def joint_end(self) -> str:
        """Where each member ended, as verify.team.JointCounts.key writes a joint end."""
        return " + ".join(f"{m.vehicle}:{m.end or 'waiting'}" for m in self.members)

    def lines(self) -> list[str]:
        """The joint events in time order, each naming its vehicle."""
        return [f"[{_clock(e.event.t)}] {e.line}" for e in self.ordered_events()]

    def ordered_events(self) -> list[TeamEvent]:
        return sorted(self.events, key=lambda e: e.event.t)

    def to_json(self) -> dict[str, Any]:
        return {
            "vehicles": list(self.vehicles),
            "joint_end": self.joint_end(),
            "meetings": [m.to_json() for m in self.meetings],
            "members": [{
                "vehicle": m.vehicle,
                "state": m.state,
                # The member's own single-run fields, as a one-vehicle record holds them, so
                # readers of records (the execution check) read a member like a vehicle; its
                # events are the team's events that name it.
                "orders": {"id": m.orders.id, "digest": digest(m.orders)},
                "goals": list(m.sim.run.goals),
                "outcomes": list(m.sim.run.outcomes),
                "terminal": m.sim.run.terminal,
                "terminal_kind": m.sim.run.terminal_kind,
                "steps": m.sim.steps,
                "legs_flown": list(m.sim.flown_legs),
                "unmonitored_constraints": list(m.sim.unmonitored),
                "runs": [r.to_json() for r in m.sim.runs],
                "energy": {"capacity_wh": round(m.sim.capacity_wh, 3),
                           "used_wh": round(m.sim.energy_used_wh, 3)},
                "sim_time_s": round(m.sim.time_s, 3),
                "inputs": {"faults": list(m.sim.fault_log)},
                "rule_firings": dict(sorted(m.sim.rule_firings.items())),
            } for m in self.members],
            "events": [e.to_json() for e in self.ordered_events()],
            "events_dropped": self.events_dropped,
        }

    # ------------------------------------------------------------------------------ meetings

    def _judge_meetings(self) -> None:
        fired = True
        any_fired = False
        while fired and self.state == "running":
            fired = False
            for meet in sorted(self.participants):
                if self._assembled(meet):
                    self._fire(meet)
                    fired = any_fired = True
        for member in self.members:
            held = member.at_meeting()
            if held is None:
                continue
            if member.state == "running":
                member.state = "waiting"
                names = [v for v in self.participants[held] if v != member.vehicle]
                self._emit(member, "holding",
                           f"Holds at meeting {held} and waits for "
                           f"{', '.join(names) or 'a partner'}.", {"meet": held})
            why = self._cannot_come(member, held)
            if why is not None:
                self._deadlock(member, held, why)
        # Nothing moves and nothing met: every member left holds for another that holds
        # elsewhere first (a circular wait).
        left = [m for m in self.members if m.state not in ("finished", "deadlocked")]
        if left and not any_fired and all(m.at_meeting() is not None for m in left):
            for member in left:
                stuck = member.at_meeting()
                assert stuck is not None
                partners = [self.member(v) for v in self.participants[stuck]
                            if v != member.vehicle]
                why = " and ".join(self._where(p, stuck) for p in partners
                                   if p.at_meeting() != stuck) or "no partner comes"
                self._deadlock(member, stuck, why)

    def _assembled(self, meet: str) -> bool:
        names = self.participants[meet]
        return len(names) >= 2 and all(self.member(v).at_meeting() == meet for v in names)

    def _fire(self, meet: str) -> None:
        members = [self.member(v) for v in self.participants[meet]]
        # One moment for all: a member's clock may lag the latest by part of a step, which
        # it spends holding there.
        t = max(m.sim.time_s for m in members)
        for member in members:
            self._loiter(member, t - member.sim.time_s)
            member.sim.time_s = t
        outcome, reason = self._shared_outcome(members)
        goals = {m.vehicle: m.sim.current_goal or "" for m in members}
        self.meetings.append(Meeting(meet, tuple(goals), self.time_s, outcome, reason, goals))
        for member in members:
            others = ", ".join(v for v in goals if v != member.vehicle)
            text = f"Meets {others} at meeting {meet}: shared outcome {outcome} ({reason})."
            self._emit(member, "meeting", text,
                       {"meet": meet, "outcome": outcome, "with": [v for v in goals
                                                                   if v != member.vehicle]})
            member.state = "running"
            member.sim.end_goal(outcome, f"meeting {meet} with {others}: {reason}")
            if member.sim.state == "finished":
                member.state = "finished"

    @staticmethod
    def _loiter(member: Member, seconds: float) -> None:
        """Holding at a meeting for partners is charged at the simulation's holding power
        (40% of cruise power), never beyond what the battery holds."""
        sim = member.sim
        if seconds > 0:
            sim.energy_used_wh += min(sim.energy_remaining_wh,
                                      LOITER_POWER_FRACTION * sim.power_w * seconds / 3600.0)

    def _shared_outcome(self, members: list[Member]) -> tuple[str, str]:
        for member in members:
            goal = member.sim.current_goal or ""
            scripted = member.source.scripted_meeting.get(goal)
            if scripted is not None:
                return scripted, f"replayed from {member.vehicle}'s path"
        seen = []
        for member in members:
            active = member.sim.active
            if active is not None and active.suggestion is not None:
                seen.append((WORST_FIRST.index(active.suggestion[0]), member.vehicle,
                             active.suggestion))
        if seen:
            _, vehicle, (outcome, because) = min(seen)
            return outcome, f"{vehicle} saw: {because}"
        return "succeed", "every member is at the meeting"

    def _cannot_come(self, member: Member, meet: str) -> str | None:
        """Why some partner can no longer come to `meet` (the TEAM finding's words), or None."""
        names = self.participants[meet]
        if len(names) < 2:
            return f"no other member names meeting {meet}"
        reasons = [self._where(self.member(v), meet) for v in names
                   if v != member.vehicle and not self.member(v).can_still_meet(meet)]
        return " and ".join(reasons) or None

    def _where(self, partner: Member, meet: str) -> str:
        sim = partner.sim
        if partner.state == "finished":
            terminal = sim.run.terminal
            label = sim.terminals[terminal].label if terminal in sim.terminals else "no terminal"
            return f"{partner.vehicle} has ended at {terminal or 'no terminal'} ({label})"
        goal = sim.current_goal or "?"
        other = partner.at_meeting()
        if partner.state == "deadlocked" or (other is not None and other != meet):
            return f"{partner.vehicle} waits at {goal} for meeting {other or '?'} first"
        return (f"{partner.vehicle} has gone past it (now at {goal}, from which no goal of "
                f"meeting {meet} can be reached)")

    def _deadlock(self, member: Member, meet: str, why: str) -> None:
        goal = member.sim.active.goal if member.sim.active is not None else None
        where = f"{goal.id} ({goal.label})" if goal is not None else "?"
        text = (f"Meeting {meet} deadlocks: {member.vehicle} waits at {where}, but {why}, so it "
                f"can no longer come (TEAM). The wait ends here: {member.vehicle} is left "
                "waiting and the rehearsal goes on without it.")
        self._emit(member, "deadlock", text, {"meet": meet, "reason": why})
        member.state = "deadlocked"

    # ------------------------------------------------------------------------------ events

    def _listener(self, vehicle: str) -> Any:
        def listen(event: Event) -> None:
            self._add(vehicle, event)
        return listen

    def _add(self, vehicle: str, event: Event) -> None:
        if len(self.events) < self.limits.max_events:
            self.events.append(TeamEvent(vehicle, event))
        else:
            self.events_dropped += 1

    def _emit(self, member: Member, kind: str, text: str, data: dict[str, Any]) -> None:
        self._add(member.vehicle, Event(round(member.sim.time_s, 3), kind, text,
                                        member.sim.current_goal, data))

    def _emit_all(self, kind: str, text: str) -> None:
        # After every member's last event: a member's clock may pass the tick by a step.
        t = max(self.time_s, *(m.sim.time_s for m in self.members))
        for member in self.members:
            self._add(member.vehicle, Event(round(t, 3), kind, text))

    def _maybe_finish(self) -> None:
        if self.state == "running" and all(
                m.state in ("finished", "deadlocked") for m in self.members):
            self._finish()

    def _finish(self) -> None:
        self.state = "finished"
        self._emit_all("team_end", f"Team rehearsal ended: {self.joint_end()}.")


def _clock(t: float) -> str:
    hours, rem = divmod(int(t), 3600)
    return f"{hours}h{rem // 60:02d}m"
