"""How a goal ends (the monitors): default rules, constraint monitors, the energy check and
the plan, each proposing an outcome that the outcome source decides."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..verify.expressions import identifiers
from .contingency import RuleVerdict
from .monitor import Monitor
from .sim_energy import energy_choice
from .sim_model import (
    CHECK_PERIOD_S,
    ENERGY_CHECK_S,
    IMMINENT_S,
    POSTURE_ACTIONS,
    QUESTION,
    SCRIPTED_CUT,
    ActiveGoal,
)
from .sim_plans import is_recovery
from .sim_sensing import observations, values
from .world import FAR_M

if TYPE_CHECKING:
    from .sim import Simulation


def judge(sim: Simulation, active: ActiveGoal) -> None:
    if sim.time_s >= sim._next_check_s or active.finished_plan:
        sim._next_check_s = sim.time_s + CHECK_PERIOD_S
        if check(sim, active):
            return
    # 4. The plan.
    if active.finished_plan:
        propose(sim, active, "succeed", "the plan is complete", {}, plan_done=True)
    elif sim.time_s - active.started_s > sim.limits.max_goal_s:
        propose(sim, active, "fail", "the goal ran out of time", {}, plan_done=True)
    elif active.scripted and active.scripted != "succeed" \
            and active.progress >= SCRIPTED_CUT[active.scripted]:
        sim._end_goal(active, active.scripted, "replayed from the traversal")


def check(sim: Simulation, active: ActiveGoal) -> bool:
    """Rules, monitors and energy; True when the goal ended or now waits."""
    goal_id = active.goal.id
    # 1. Default rules: the extension of the theory under what the vehicle observes.
    if sim.contingency.active:
        action = sim.contingency.planned_action(active.goal, sim.contingency_actions)
        verdict = sim.contingency.check(observations(sim, action), action)
        assert verdict is not None
        for rule in verdict.fired_new:
            sim.rule_firings[rule] = sim.rule_firings.get(rule, 0) + 1
        if verdict.fired_new:
            sim._emit("rules", "Rules fired: " + ", ".join(verdict.fired_new) + ".",
                      goal_id, {"fired": list(verdict.fired_new)})
        if verdict.refused and obey(sim, active, action, verdict):
            return True
    # 2. Constraint monitors, now and a little ahead.
    now = values(sim, needed=sim.needed)
    ahead = values(sim, IMMINENT_S, needed=sim.needed)
    for monitor in sim.monitors:
        if not monitor.applies(goal_id):
            continue
        if monitor.holds(now, active.facts) is False or \
                monitor.holds(ahead, active.facts) is False:
            reason = f"{monitor.constraint_id} would be violated: {monitor.expr}"
            if propose(sim, active, "violate", reason,
                       {"constraint": monitor.constraint_id,
                        "values": _read_values(monitor, now)}):
                return True
            break
    # 3. Energy (seed 001): give up a goal that can no longer be finished with the reserve
    # to reach recovery, at the consumption actually measured so far.
    if sim.time_s - active.last_energy_check >= ENERGY_CHECK_S:
        active.last_energy_check = sim.time_s
        give_up = energy_choice(sim, active)
        if give_up is not None and propose(sim, active, "fail", give_up[0], give_up[1]):
            return True
    return sim.energy_remaining_wh <= 0.0 and propose(sim,
        active, "fail", "the battery is empty", {}
    )


def obey(sim: Simulation, active: ActiveGoal, action: str, verdict: RuleVerdict) -> bool:
    """A refused planned action: obey the safe action. A change of depth on the way home
    keeps the goal; anything else ends it (fail when the goal was dropped, violate for a
    safety action). True when the goal ended or now waits."""
    safe = verdict.safe_action
    v = sim.vehicle
    homeward = is_recovery(sim, active.goal)
    if safe in POSTURE_ACTIONS and homeward:
        if safe == "surface" and not v.forced_surface:
            v.forced_surface = True
            sim._emit("safe_action", f"Safety action: surface ({verdict.reason})",
                      active.goal.id, {"action": safe, "rules": list(verdict.because)})
        return False
    if safe in ("surface", "shutdown", "shut_down"):
        v.forced_surface = True
    data = {"planned": action, "action": safe, "rules": list(verdict.because),
            "explanation": verdict.reason}
    text = (f"rules refuse {action}" + (f" and require {safe}" if safe else "")
            + f": {verdict.reason}")
    return propose(sim, active, verdict.outcome, text, data)


def propose(sim: Simulation, active: ActiveGoal, outcome: str, reason: str, data: dict[str, Any],
            *, plan_done: bool = False) -> bool:
    """The simulation's view of how the goal ends; the source decides. True when the goal
    ended or now waits."""
    decision = sim.source.decide(outcome, plan_done=plan_done, scripted=active.scripted)
    if decision == "end":
        sim._emit("decision", reason, active.goal.id, {"outcome": outcome, **data})
        sim._end_goal(active, outcome, reason)
        return True
    if decision == "scripted" and active.scripted:
        sim._end_goal(active, active.scripted, "replayed from the traversal")
        return True
    if decision == "wait":
        sim.state = "waiting_for_outcome"
        suggestion = active.suggestion or (outcome, reason)
        sim._emit("waiting", QUESTION,
                  active.goal.id, {"suggested": suggestion[0], "because": suggestion[1]})
        return True
    if active.suggestion is None and not plan_done:
        # Manual and scripted sources keep going; remember what the simulation saw.
        active.suggestion = (outcome, reason)
        sim._emit("observed", reason, active.goal.id, {"outcome": outcome, **data})
    return False


def _read_values(monitor: Monitor, values: dict[str, float | bool | str]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for name in sorted(identifiers(monitor.expr)):
        if name in values:
            value = values[name]
            out[name] = round(value, 3) if isinstance(value, float) and value < FAR_M else value
    return out
