"""A live team rehearsal: `Rehearsal`'s lifecycle (thread, viser server, pace,
stop and record) around a `TeamSimulation` and its one `TeamScene`.

Outcomes come from each member's simulation (or one path of its own orders) and meetings are
joint, so there is nothing to choose: `choose` is refused with the reason. Faults name their
vehicle (`vehicle-2:leak`; without one, every member). The record is `countersign.rehearsal/1`
with the team's joint figures at the top (every member's runs, events naming their vehicle,
energy summed) and `team` holding each member's own figures, the meetings and the joint end.
"""

from __future__ import annotations

import logging
import secrets
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import viser

from ..orders.canonical import digest as orders_digest
from ..orders.model import Chart, Orders
from .manager import (
    FRAME_S,
    MAX_FAULTS,
    MAX_FRAME_STEPS,
    MIN_AUTO_FRAME_S,
    SKIP_FRAME_S,
    STATUS_EVENTS,
    Clock,
    Frames,
    Rehearsal,
    RehearsalOptions,
    RehearsalState,
)
from .record import FORMAT
from .sim import FAULTS, Limits
from .sim_model import UnknownFault
from .team import TeamSimulation
from .team_scene import TeamScene

log = logging.getLogger("countersign.rehearse")
TEAM_FRAME_S = 120.0  # auto pace: simulated seconds per frame (a 12 h mission in ~18 s)


class TeamRehearsal(Rehearsal):
    def __init__(
        self,
        orders: Orders,
        *,
        owner: str,
        options: RehearsalOptions,
        paths: Mapping[str, int] | None = None,
        headless: bool = False, gated: bool = True,
        limits: Limits | None = None,
        charts: Sequence[Chart] = (),
        idle_timeout_s: float = 900.0,
        on_stopped: Callable[[Rehearsal], None] | None = None,
    ) -> None:
        self.id = secrets.token_urlsafe(24)
        self.owner = owner
        # Faults may name a member (`vehicle-2:leak`): TeamSimulation reads them.
        replace(options, faults=()).validated()
        if len(options.faults) > MAX_FAULTS:
            raise ValueError(f"at most {MAX_FAULTS} faults")
        self.options = options
        if self.options.path_index is not None:
            raise ValueError("a team replays one path per member: give paths by vehicle")
        self.orders_digest = orders_digest(orders)
        self.orders_id = orders.id
        self.orders_title = orders.title or orders.id
        self._limits = limits or Limits()
        self.team = TeamSimulation(orders, seed=self.options.seed, source=self.options.source,
                                   paths=paths, faults=self.options.faults,
                                   limits=self._limits, charts=charts)
        self.paths = dict(sorted((paths or {}).items()))
        # The base class's Simulation slot holds the first member (never stepped through it):
        # every method that would step or judge by it (_loop, status, ...) is overridden.
        self._sim = self.team.members[0].sim
        self._team_scene: TeamScene | None = None
        self._setup(headless=headless, gated=gated, idle_timeout_s=idle_timeout_s,
                    on_stopped=on_stopped, thread_prefix="team")

    def _open_scene(self, server: viser.ViserServer) -> None:
        self._team_scene = TeamScene(server, self.team, title=self.orders_title)

    # ------------------------------------------------------------------------------ API

    @property
    def state(self) -> RehearsalState:
        return "stopped" if self._stopped else self.team.state

    def status(self) -> dict[str, Any]:
        self.touch()
        with self._lock:
            team = self.team
            members = [_member_status(m) for m in team.members]
            return {
                "id": self.id,
                "state": self.state,
                "source": self.options.source,
                "seed": self.options.seed,
                "path_index": None,
                "run": 1,
                "current_goal": None,
                "step": len(team.meetings),
                "outcomes": [],
                "terminal": None,
                "energy_wh": round(sum(m["energy_wh"] for m in members), 3),
                "energy_used_wh": round(sum(m["energy_used_wh"] for m in members), 3),
                "capacity_wh": round(sum(m["capacity_wh"] for m in members), 3),
                "sim_time_s": round(team.time_s, 3),
                "speed": self._speed,
                "pace": "auto" if self._speed is None else "fixed",
                "skipping": self._skipping,
                "frames": self.frames,
                "first_question_frame": None,
                "faults": sorted({f"{m.vehicle}:{f}" for m in team.members
                                  for f in m.sim.active_faults}),
                "queued_faults": [],
                "fault_notice": self._notice,
                "events": [e.to_json() for e in team.ordered_events()[-STATUS_EVENTS:]],
                "port": self.port,
                "team": {"members": members,
                         "meetings": [m.to_json() for m in team.meetings],
                         "joint_end": team.joint_end() if team.state == "finished" else None},
            }

    def choose(self, outcome: str) -> None:
        self.touch()
        raise ValueError("a team's outcomes come from each member's simulation and its "
                         "meetings; there is no outcome to choose")

    def inject(self, fault: str) -> str:
        """`VEHICLE:FAULT` for one member, `FAULT` for every member."""
        self.touch()
        vehicle, sep, name = fault.partition(":")
        if not sep:
            vehicle, name = "", fault
        if name not in FAULTS:
            raise UnknownFault(f"fault must be one of {', '.join(FAULTS)}, not {str(name)[:40]!r}")
        with self._lock:
            if self._stopped:
                raise ValueError("the rehearsal is stopped: no fault can be injected")
            try:
                members = [self.team.member(vehicle)] if vehicle else list(self.team.members)
            except KeyError:
                raise UnknownFault(f"no vehicle {vehicle[:40]!r} in the team") from None
            texts = [f"{m.vehicle}: {m.sim.inject(name)}" for m in members
                     if m.state not in ("finished", "deadlocked")]
            if not texts:
                raise ValueError("every vehicle named has ended: no fault was injected")
            text = " ".join(texts)
            self._notice = {"fault": name, "text": text, "state": "applied"}
            self._dirty = True
        self._wake.set()
        return text

    def skip(self) -> None:
        """Run to the next meeting (or the end) as fast as frames allow."""
        self.touch()
        with self._lock:
            if self._stopped or self.team.state != "running":
                raise ValueError(f"nothing to skip: the rehearsal is {self.state}")
            self._skipping = True
        self._wake.set()

    # ------------------------------------------------------------------------------ thread

    def _run(self) -> None:
        try:
            self._loop()
        except Exception as exc:
            log.exception("team rehearsal %s failed", self.id)
            with self._lock:
                self.team._emit_all("error", f"Simulation error: {type(exc).__name__}: {exc}")
                self.team.state = "finished"

    def _loop(self) -> None:
        """The base loop's pace and idling, judged by the team's state (not a member's)."""
        next_frame = time.perf_counter()
        while not self._stop_event.is_set():
            with self._lock:
                if self.team.state == "running":
                    self._advance_frame()
                    self._dirty = True
                if self._dirty:
                    self._push_frame()
                    self._dirty = False
                state = self.team.state
            next_frame += FRAME_S
            delay = max(0.0, next_frame - time.perf_counter())
            if delay == 0.0:
                next_frame = time.perf_counter()
            if state != "running":
                delay = 0.5  # finished: nothing to compute
                if self.idle_for() > self.idle_timeout_s:
                    self._stop_idle()
                    return
            self._wake.wait(delay)
            self._wake.clear()

    def _frame_seconds(self) -> float:
        if self._skipping:
            return SKIP_FRAME_S
        pace = self._speed * FRAME_S if self._speed is not None else max(MIN_AUTO_FRAME_S,
                                                                          TEAM_FRAME_S)
        return min(pace, MAX_FRAME_STEPS * self._limits.step_s)

    def _advance_frame(self) -> None:
        team = self.team
        meetings = len(team.meetings)
        team.advance(self._frame_seconds())
        self.frames += 1
        if self._skipping and (team.state != "running" or len(team.meetings) != meetings):
            self._skipping = False

    def _clock(self) -> Clock:
        return self.team

    def _frames(self) -> Frames | None:
        return self._team_scene

    # ------------------------------------------------------------------------------ record

    def _record_json(self) -> dict[str, Any]:
        team = self.team
        first = team.members[0].sim
        world = first.world
        lat, lon = world.to_latlon(world.recovery)
        detail = team.to_json()
        capacity = sum(m.sim.capacity_wh for m in team.members)
        used = sum(m.sim.energy_used_wh for m in team.members)
        runs = [r for m in detail["members"] for r in m["runs"]]
        return {
            "format": FORMAT,
            "orders": {"id": self.orders_id, "digest": self.orders_digest},
            "options": self.options.to_json(),
            "seed": self.options.seed,
            "state": "stopped_early" if team.state != "finished" else "finished",
            "inputs": {"faults": [f"{m.vehicle}:{f}" for m in team.members
                                  for f in m.sim.fault_log], "choices": []},
            "runs": runs,
            "goals": [],
            "outcomes": [],
            "terminal": None,
            "terminal_kind": None,
            "sim_time_s": round(team.time_s, 3),
            "steps": sum(m.sim.steps for m in team.members),
            "events": detail.pop("events"),
            "events_dropped": detail.pop("events_dropped"),
            "rule_firings": {},
            "rules": any(m.sim.contingency.active for m in team.members),
            "energy": {"capacity_wh": round(capacity, 3), "used_wh": round(used, 3),
                       "remaining_wh": round(max(0.0, capacity - used), 3)},
            "unmonitored_constraints": sorted({f"{m.vehicle}/{c}" for m in team.members
                                               for c in m.sim.unmonitored}),
            "legs_flown": [],
            "world": {"recovery": [round(lat, 6), round(lon, 6)],
                      "generated_lane": world.generated_lane,
                      "contacts": sum(len(m.sim.world.contacts) for m in team.members)},
            "team": {**detail, "paths": self.paths},
        }


def _member_status(member: Any) -> dict[str, Any]:
    sim = member.sim
    active = sim.active
    run = sim.run
    return {
        "vehicle": member.vehicle,
        "state": member.state,
        "current_goal": None if active is None or member.state in ("finished", "deadlocked")
        else {"id": active.goal.id, "title": active.goal.label,
              "behavior": active.goal.behavior, "area": active.goal.area,
              "progress": round(active.progress, 4)},
        "outcomes": [{"goal": g, "outcome": o}
                     for g, o in zip(run.goals, run.outcomes, strict=False)],
        "terminal": run.terminal,
        "energy_wh": round(sim.energy_remaining_wh, 3),
        "energy_used_wh": round(sim.energy_used_wh, 3),
        "capacity_wh": round(sim.capacity_wh, 3),
        "sim_time_s": round(sim.time_s, 3),
    }
