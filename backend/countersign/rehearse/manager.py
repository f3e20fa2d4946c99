"""Rehearsal lifecycle: one simulation thread and one viser server per
rehearsal, created and stopped by the app.

    manager = RehearsalManager(max_active=16, idle_timeout_s=900)
    rehearsal = manager.start(orders, owner="alice", options=RehearsalOptions(source="manual"))
    rehearsal.port            # viser on 127.0.0.1: the app proxies /rehearsal/{id}/ to it
    rehearsal.choose("fail")  # the same as clicking Fail in the viser GUI
    record = manager.stop(rehearsal.id)

Each rehearsal's thread advances the simulation one frame every 50 ms, pushes the frame to the
scene and waits; a rehearsal waiting for a manual outcome sleeps until `choose`. The pace is
counted in frames, not wall time, so it holds on a loaded machine: at the default (auto) pace
each goal's plan plays in about GOAL_FRAMES frames whatever its length (time compression while
nothing happens), slowed for a few frames after something worth seeing (a fault, an observed
outcome); `skip()` runs to the next decision at once; a fixed `speed` plays that many simulated
seconds per wall second instead. `stop()` ends the thread, stops the viser server (its port and
threads) and seals the recording into the record's HTML replay. A rehearsal nobody touched
for `idle_timeout_s` (no API call, no browser connected) stops itself.
"""

from __future__ import annotations

import logging
import secrets
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, Protocol

import viser
from cachetools import FIFOCache

from ..orders.canonical import digest as orders_digest
from ..orders.model import OUTCOMES, Chart, Orders
from . import viser_gate
from .record import FORMAT, RehearsalRecord
from .scene import Scene
from .sim import FAULTS, QUESTION, FaultSpec, Limits, Simulation
from .sim_model import UnknownFault
from .sources import SOURCES, make_source

log = logging.getLogger("countersign.rehearse")
FRAME_S = 0.05
GOAL_FRAMES = 60  # auto pace: a goal's plan in about 3 s at 20 frames a second
MIN_AUTO_FRAME_S = 1.0  # ... but never slower than 20x real time
SLOW_FRAMES = 8  # after a notable event, this many frames at a quarter of the pace
NOTABLE_EVENTS = frozenset({"fault", "fault_queued", "observed", "safe_action", "current"})
MAX_FRAME_STEPS = 5_000  # simulated seconds per frame at most (bounded work per frame)
SKIP_FRAME_S = 20_000.0  # skipping: simulated seconds per frame until the next decision
RECORD_SPEED = 200.0  # the HTML replay plays 200 simulated seconds per second


class Clock(Protocol):
    """What a rehearsal drives and records: one vehicle's simulation, or a team's."""

    time_s: float

    @property
    def state(self) -> str: ...

    def advance(self, seconds: float) -> None: ...


class Frames(Protocol):
    """The 3D scene a rehearsal sends a frame to."""

    def frame(self) -> None: ...
MIN_SPEED, MAX_SPEED = 0.1, 1_000_000.0
MAX_FAULTS = 20
STATUS_EVENTS = 20
MAX_STOPPED = 256  # stopped rehearsals remembered for status and repeated stop()
SourceName = Literal["manual", "replay", "tour", "simulate"]
RehearsalState = Literal["running", "waiting_for_outcome", "finished", "stopped"]


class RehearsalLimit(RuntimeError):
    """Too many rehearsals are running; stop one first."""


@dataclass(frozen=True)
class RehearsalOptions:
    source: SourceName = "manual"
    seed: int = 0
    path_index: int | None = None
    faults: tuple[str, ...] = ()
    speed: float | None = None  # simulated seconds per wall second; None: the auto pace

    def validated(self) -> RehearsalOptions:
        if self.source not in SOURCES:
            raise ValueError(f"source must be one of {', '.join(SOURCES)}, not {self.source!r}")
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) \
                or not 0 <= self.seed < 2**63:
            raise ValueError("seed must be an integer between 0 and 2^63-1")
        if self.path_index is not None and (
            not isinstance(self.path_index, int) or self.path_index < 1
        ):
            raise ValueError("path_index must be a positive integer (paths count from 1)")
        if len(self.faults) > MAX_FAULTS:
            raise ValueError(f"at most {MAX_FAULTS} faults")
        for fault in self.faults:
            FaultSpec.parse(fault)
        if self.speed is not None and not MIN_SPEED <= float(self.speed) <= MAX_SPEED:
            raise ValueError(f"speed must be between {MIN_SPEED:g} and {MAX_SPEED:g}")
        return self

    def to_json(self) -> dict[str, Any]:
        # Speed is presentation only: it is not part of the record.
        return {"source": self.source, "seed": self.seed, "path_index": self.path_index,
                "faults": list(self.faults)}


class Rehearsal:
    def __init__(
        self,
        orders: Orders,
        *,
        owner: str,
        options: RehearsalOptions,
        headless: bool = False, gated: bool = True, controls: bool = False,
        limits: Limits | None = None,
        charts: Sequence[Chart] = (),
        idle_timeout_s: float = 900.0,
        on_stopped: Callable[[Rehearsal], None] | None = None,
    ) -> None:
        self.id = secrets.token_urlsafe(24)
        self.owner = owner
        self.options = options.validated()
        self.orders_digest = orders_digest(orders)
        self.orders_id = orders.id
        self.orders_title = orders.title or orders.id
        self._limits = limits or Limits()
        source = make_source(options.source, orders, path_index=options.path_index,
                             max_tour_paths=self._limits.max_tour_paths)
        self._sim = Simulation(orders, seed=options.seed, source=source,
                               faults=options.faults, limits=self._limits, charts=charts)
        self._controls = controls
        self._setup(headless=headless, gated=gated, idle_timeout_s=idle_timeout_s,
                    on_stopped=on_stopped, thread_prefix="rehearsal")

    def _setup(self, *, headless: bool, gated: bool, idle_timeout_s: float,
               on_stopped: Callable[[Rehearsal], None] | None, thread_prefix: str) -> None:
        """The state every rehearsal keeps, and its viser server unless headless (the scene
        itself is `_open_scene`'s)."""
        self._lock = threading.RLock()
        self._wake = threading.Event()
        self._stop_event = threading.Event()
        self._stopped = False
        self._sealed = threading.Event()  # set once stop() has sealed the record
        speed = self.options.speed
        self._speed: float | None = None if speed is None else float(speed)
        self.frames = 0  # frames simulated: the unit of the pace
        self.first_question_frame: int | None = None
        self._skipping = False
        self._slow_frames = 0
        self._events_paced = 0
        self._dirty = True  # the scene lags the simulation: push a frame
        self._notice: dict[str, str] | None = None
        self._on_stopped = on_stopped
        self.idle_timeout_s = idle_timeout_s
        self._record: RehearsalRecord | None = None
        self._html: bytes | None = None
        self._recorded_sim_s = 0.0
        self.last_activity = time.monotonic()
        self._server: viser.ViserServer | None = None
        self._scene: Scene | None = None
        self._serializer: Any = None
        self.port = 0
        # Sent by the app's proxy to viser (viser_gate.py): viser's port answers nobody else.
        # The CLI's own viewer (gated=False) is opened by the user's browser straight on it.
        self.viewer_secret = secrets.token_urlsafe(32)
        if not headless:
            self._server = viser.ViserServer(host="127.0.0.1", port=0,
                                             label=self.orders_title[:80], verbose=False)
            try:
                if gated:
                    viser_gate.install(self._server, self.viewer_secret)
                self.port = self._server.get_port()
                self._open_scene(self._server)
                frames = self._frames()
                if frames is not None:
                    frames.frame()
                # Record from here on: the serializer snapshots the scene so far, then
                # collects every later scene message; frames insert the simulated time.
                self._serializer = self._server.get_scene_serializer()
            except BaseException:
                self._server.stop()
                raise
        self._thread = threading.Thread(target=self._run,
                                        name=f"{thread_prefix}-{self.id[:8]}", daemon=True)

    def _open_scene(self, server: viser.ViserServer) -> None:
        self._scene = Scene(
            server, self._sim, title=self.orders_title,
            on_choose=self.choose, on_inject=self.inject, on_speed=self.set_speed,
            on_skip=self.skip, speed=self._speed, manual=self.options.source == "manual",
            controls=self._controls,
        )

    # ------------------------------------------------------------------------------ API

    @property
    def state(self) -> RehearsalState:
        return "stopped" if self._stopped else self._sim.state

    def start(self) -> None:
        self._thread.start()

    def status(self) -> dict[str, Any]:
        self.touch()
        with self._lock:
            sim = self._sim
            active = sim.active
            current = None
            if active is not None:
                goal = active.goal
                current = {"id": goal.id, "title": goal.label, "behavior": goal.behavior,
                           "area": goal.area, "progress": round(active.progress, 4)}
            run = sim.run
            status: dict[str, Any] = {
                "id": self.id,
                "state": self.state,
                "source": self.options.source,
                "seed": self.options.seed,
                "path_index": run.path_index,
                "run": len(sim.runs),
                "current_goal": current,
                "step": len(run.outcomes),
                "outcomes": [{"goal": g, "outcome": o}
                             for g, o in zip(run.goals, run.outcomes, strict=False)],
                "terminal": run.terminal,
                "energy_wh": round(sim.energy_remaining_wh, 3),
                "energy_used_wh": round(sim.energy_used_wh, 3),
                "capacity_wh": sim.capacity_wh,
                "sim_time_s": round(sim.time_s, 3),
                "speed": self._speed,
                "pace": "auto" if self._speed is None else "fixed",
                "skipping": self._skipping,
                "frames": self.frames,
                "first_question_frame": self.first_question_frame,
                "faults": sorted(sim.active_faults),
                "queued_faults": list(sim.queued_faults),
                "fault_notice": self._notice,
                "events": [e.to_json() for e in sim.events[-STATUS_EVENTS:]],
                "port": self.port, **sim.refined_status(),
            }
            if sim.state == "waiting_for_outcome" and active is not None:
                suggestion = active.suggestion
                status["question"] = QUESTION
                status["suggested"] = (
                    {"outcome": suggestion[0], "because": suggestion[1]} if suggestion else None
                )
            return status

    def choose(self, outcome: str) -> None:
        """A manual outcome (API or GUI click); ValueError on a bad outcome or state."""
        self.touch()
        if outcome == "constraint":
            outcome = "violate"
        if outcome not in OUTCOMES:
            raise ValueError(f"outcome must be one of succeed, fail, violate (or constraint), "
                             f"not {str(outcome)[:40]!r}")
        with self._lock:
            if self._stopped:
                raise ValueError("the rehearsal is stopped")
            if self.options.source != "manual":
                raise ValueError(f"outcomes come from the {self.options.source} source here")
            self._sim.choose(outcome)
            self._skipping = False
            self._dirty = True
        self._wake.set()

    def inject(self, fault: str) -> str:
        """Apply the fault now, or queue it while a goal waits for its outcome; the text says
        which (ValueError, with the reason, when it is refused)."""
        self.touch()
        if fault not in FAULTS:
            raise UnknownFault(f"fault must be one of {', '.join(FAULTS)}, not {str(fault)[:40]!r}")
        with self._lock:
            if self._stopped:
                raise ValueError("the rehearsal is stopped: no fault can be injected")
            text = self._sim.inject(fault)
            self._notice = {"fault": fault, "text": text,
                            "state": "queued" if fault in self._sim.queued_faults else "applied"}
            self._dirty = True
        self._wake.set()
        return text

    def skip(self) -> None:
        """Run to the next decision (an outcome chosen or asked for) as fast as frames allow."""
        self.touch()
        with self._lock:
            if self._stopped or self._sim.state != "running":
                state = self.state.replace("_", " ")
                raise ValueError(f"nothing to skip: the rehearsal is {state}")
            self._skipping = True
        self._wake.set()

    def set_speed(self, speed: float | None) -> None:
        """Simulated seconds per wall second, or None for the auto pace."""
        self.touch()
        with self._lock:
            self._speed = None if speed is None else min(MAX_SPEED, max(MIN_SPEED, float(speed)))
        self._wake.set()

    def record(self) -> RehearsalRecord:
        with self._lock:
            if self._record is not None:
                return self._record
            record = RehearsalRecord(self._record_json(), self._html)
            if self._stopped:
                self._record = record
            return record

    def touch(self) -> None:
        self.last_activity = time.monotonic()

    def idle_for(self) -> float:
        server = self._server
        if server is not None and not self._stopped and server.get_clients():
            self.touch()  # someone is watching
        return time.monotonic() - self.last_activity

    def stop(self) -> RehearsalRecord:
        """Stop the thread and the viser server and seal the record. Safe to call twice and
        from several threads: later callers wait for the first to finish."""
        with self._lock:
            first = not self._stopped
            self._stopped = True
        if not first:
            if threading.current_thread() is not self._thread:
                self._sealed.wait(timeout=60.0)
            if self._record is None:
                raise RuntimeError("the rehearsal is still being stopped")
            return self._record
        self._stop_event.set()
        self._wake.set()
        try:
            if self._thread.is_alive() and threading.current_thread() is not self._thread:
                self._thread.join(timeout=10.0)
            with self._lock:
                try:
                    if self._serializer is not None:
                        self._html = self._serializer.as_html().encode("utf-8")
                except Exception as exc:  # the replay is extra: never lose the record to it
                    log.warning("rehearsal %s: no replay: %r", self.id, exc)
                    self._html = None
                finally:
                    self._serializer = None
                    if self._server is not None:
                        self._server.stop()
                self._record = RehearsalRecord(self._record_json(), self._html)
                record = self._record
        finally:
            self._sealed.set()
        if self._on_stopped is not None:
            self._on_stopped(self)
        return record

    # ------------------------------------------------------------------------------ thread

    def _run(self) -> None:
        try:
            self._loop()
        except Exception as exc:
            with self._lock:
                self._sim._emit("error", f"Simulation error: {type(exc).__name__}: {exc}")
                self._sim.state = "finished"

    def _loop(self) -> None:
        next_frame = time.perf_counter()
        while not self._stop_event.is_set():
            with self._lock:
                sim = self._sim
                if sim.state == "running":
                    self._advance_frame()
                    self._dirty = True
                if sim.state == "waiting_for_outcome" and self.first_question_frame is None:
                    self.first_question_frame = self.frames
                if self._dirty:
                    # Also after a choice, a fault or the end, so the scene never lags.
                    self._push_frame()
                    self._dirty = False
                state = sim.state
            if state == "finished" and self.idle_for() > self.idle_timeout_s:
                self._stop_idle()
                return
            next_frame += FRAME_S
            delay = next_frame - time.perf_counter()
            if delay < 0:
                next_frame = time.perf_counter()
                delay = 0.0
            if state != "running":
                delay = 0.5  # waiting for a person, or finished: nothing to compute
                if self.idle_for() > self.idle_timeout_s:
                    self._stop_idle()
                    return
            self._wake.wait(delay)
            self._wake.clear()

    def _stop_idle(self) -> None:
        # From the rehearsal's own thread: stop() does not join it; if an API stop is already
        # under way, this thread just ends and lets that stop finish.
        if not self._stop_event.is_set():
            self.stop()

    def _frame_seconds(self) -> float:
        """Simulated seconds in the next frame (the pace; see the module's docstring)."""
        sim = self._sim
        if self._skipping:
            return SKIP_FRAME_S
        if self._speed is not None:
            pace = self._speed * FRAME_S
        else:
            planned = sim.active.planned_s if sim.active is not None else 0.0
            pace = max(MIN_AUTO_FRAME_S, planned / GOAL_FRAMES)
            if self._slow_frames > 0:
                self._slow_frames -= 1
                pace = max(MIN_AUTO_FRAME_S, pace / 4)
        return min(pace, MAX_FRAME_STEPS * sim.limits.step_s)

    def _decision_mark(self) -> tuple[int, int]:
        sim = self._sim
        return len(sim.runs), len(sim.run.outcomes)

    def _advance_frame(self) -> None:
        """One frame: its simulated seconds in full (no wall-clock cut, so the pace in frames
        is the same on any machine), ending early where a goal ends so that the next goal
        gets its own pace."""
        sim = self._sim
        mark = self._decision_mark()
        target = sim.time_s + self._frame_seconds()
        while sim.state == "running" and sim.time_s < target - 1e-9:
            sim.step()
            if self._decision_mark() != mark:
                break
        self.frames += 1
        if self._skipping and (sim.state != "running" or self._decision_mark() != mark):
            self._skipping = False
        events = sim.events
        if any(e.kind in NOTABLE_EVENTS for e in events[self._events_paced:]):
            self._slow_frames = SLOW_FRAMES
        self._events_paced = len(events)

    def _clock(self) -> Clock:
        """What advances and is recorded (a team rehearsal drives the team)."""
        return self._sim

    def _frames(self) -> Frames | None:
        """The scene frames go to, if there is one (a team rehearsal draws the team's)."""
        return self._scene

    def _push_frame(self) -> None:
        scene, clock = self._frames(), self._clock()
        if scene is None:
            return
        if self._serializer is not None:
            elapsed = clock.time_s - self._recorded_sim_s
            if elapsed > 0:
                self._serializer.insert_sleep(elapsed / RECORD_SPEED)
                self._recorded_sim_s = clock.time_s
        scene.frame()

    def run_headless(self, max_wall_s: float | None = None) -> None:
        """Run to the end on the calling thread (CLI, tests); manual sources stop waiting."""
        started = time.perf_counter()
        clock = self._clock()
        # With a scene, frames every simulated minute make the recorded replay move smoothly;
        # without one, large chunks keep the loop overhead negligible.
        chunk = 60.0 if self._frames() is not None else 3_600.0
        with self._lock:
            while clock.state == "running":
                clock.advance(chunk)
                self._push_frame()
                if max_wall_s is not None and time.perf_counter() - started > max_wall_s:
                    break

    # ------------------------------------------------------------------------------ record

    def _record_json(self) -> dict[str, Any]:
        sim = self._sim
        last = sim.run
        world = sim.world
        lat, lon = world.to_latlon(world.recovery)
        return {
            "format": FORMAT,
            "orders": {"id": self.orders_id, "digest": self.orders_digest},
            "options": self.options.to_json(),
            "seed": self.options.seed,
            "state": "stopped_early" if sim.state != "finished" else "finished",
            "inputs": {"faults": list(sim.fault_log), "choices": list(sim.choices)},
            "runs": [r.to_json() for r in sim.runs],
            "goals": list(last.goals),
            "outcomes": list(last.outcomes),
            "terminal": last.terminal,
            "terminal_kind": last.terminal_kind,
            "sim_time_s": round(sim.time_s, 3),
            "steps": sim.steps,
            "events": [e.to_json() for e in sim.events],
            "events_dropped": sim.events_dropped,
            "rule_firings": dict(sorted(sim.rule_firings.items())),
            "rules": sim.contingency.active,
            "energy": {
                "capacity_wh": round(sim.capacity_wh, 3),
                "used_wh": round(sim.energy_used_wh, 3),
                "remaining_wh": round(sim.energy_remaining_wh, 3),
            },
            "unmonitored_constraints": list(sim.unmonitored),
            "legs_flown": list(sim.flown_legs),
            "world": {
                "recovery": [round(lat, 6), round(lon, 6)],
                "generated_lane": world.generated_lane,
                "contacts": len(world.contacts),
            },
        }


class RehearsalManager:
    def __init__(self, *, max_active: int = 16, idle_timeout_s: float = 900.0) -> None:
        self.max_active = max_active
        self.idle_timeout_s = idle_timeout_s
        self._lock = threading.Lock()
        self._active: dict[str, Rehearsal] = {}
        self._stopped: FIFOCache[str, Rehearsal] = FIFOCache(MAX_STOPPED)

    def start(self, orders: Orders, *, owner: str, options: RehearsalOptions,
              charts: Sequence[Chart] = (), controls: bool = False,
              paths: Mapping[str, int] | None = None) -> Rehearsal:
        """A running rehearsal with its own viser server; RehearsalLimit when full,
        ValueError for options or orders that cannot be rehearsed (`paths`: team replays)."""
        self._reap()
        with self._lock:
            if len(self._active) >= self.max_active:
                raise RehearsalLimit(
                    f"{self.max_active} rehearsals are running; stop one before starting another"
                )
            # Reserve the slot before the (slow) server start so concurrent starts respect it.
            placeholder = secrets.token_urlsafe(8)
            self._active[placeholder] = None  # type: ignore[assignment]
        try:
            rehearsal: Rehearsal
            if orders.team is not None:
                # A team: every member's simulation in one clock and one scene.
                from .team_rehearsal import TeamRehearsal

                rehearsal = TeamRehearsal(orders, owner=owner, options=options, charts=charts,
                                          paths=paths, idle_timeout_s=self.idle_timeout_s,
                                          on_stopped=self._forget)
            else:
                rehearsal = Rehearsal(orders, owner=owner, options=options, charts=charts,
                                      controls=controls, idle_timeout_s=self.idle_timeout_s,
                                      on_stopped=self._forget)
        except BaseException:
            with self._lock:
                self._active.pop(placeholder, None)
            raise
        with self._lock:
            self._active.pop(placeholder, None)
            self._active[rehearsal.id] = rehearsal
        rehearsal.start()
        return rehearsal

    def get(self, rehearsal_id: str, *, touch: bool = True) -> Rehearsal | None:
        """The rehearsal; a lookup counts as activity unless `touch` is False (book-keeping
        must not keep an idle rehearsal alive)."""
        if not isinstance(rehearsal_id, str):
            return None
        with self._lock:
            rehearsal = self._active.get(rehearsal_id) or self._stopped.get(rehearsal_id)
        if rehearsal is not None and touch:
            rehearsal.touch()
        return rehearsal

    def stop(self, rehearsal_id: str) -> RehearsalRecord:
        """Stop a rehearsal and return its record; KeyError for an unknown id."""
        rehearsal = self.get(rehearsal_id)
        if rehearsal is None:
            raise KeyError(rehearsal_id)
        return rehearsal.stop()

    def shutdown(self) -> None:
        with self._lock:
            running = [r for r in self._active.values() if r is not None]
        for rehearsal in running:
            rehearsal.stop()

    def active(self) -> list[Rehearsal]:
        with self._lock:
            return [r for r in self._active.values() if r is not None]

    def _forget(self, rehearsal: Rehearsal) -> None:
        with self._lock:
            self._active.pop(rehearsal.id, None)
            self._stopped[rehearsal.id] = rehearsal

    def _reap(self) -> None:
        for rehearsal in self.active():
            if rehearsal.idle_for() > self.idle_timeout_s:
                rehearsal.stop()
