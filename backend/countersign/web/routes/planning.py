"""The planning assistant over HTTP: build a survey problem from a mission, solve it exactly."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Request
from pydantic import BaseModel, Field

from ...errors import Unprocessable
from ...orders.canonical import orders_to_json
from ...orders.reader import orders_from_data
from ...plan.draft import orders_from_plan
from ...plan.from_orders import CannotBuildProblem, problem_from_orders
from ...plan.model import problem_from_data
from ...plan.solver import PlanTimeout, PlanTooLarge, solve
from ...store import missions as service
from ..deps import EVERYONE, OPERATORS, CurrentPrincipal, Db, TransactionRoute, allow
from ..fair import PlanSlots, user_key, with_limit
from .schemas import Number, OrdersJson, PlanProblemJson, RequestBody

router = APIRouter(prefix="/api", tags=["planning"], route_class=TransactionRoute)
# A web request must not hold a worker for minutes; the command line allows longer runs.
PLAN_TIMEOUT_S = 10.0


# every number bounded, so that no input reaches arithmetic that overflows.
Latitude = Annotated[float, Field(ge=-90, le=90)]
Longitude = Annotated[float, Field(ge=-180, le=180)]
LatLon = tuple[Latitude, Longitude]
Energy = Annotated[float, Field(ge=0, le=1e9)]


class ProblemFromMission(RequestBody):
    start: LatLon
    recovery: LatLon
    battery_wh: Annotated[float, Field(gt=0, le=1e9)] | None = None
    reserve_wh: Energy = 0.0
    areas: list[str] | None = Field(default=None, max_length=64)
    rewards: dict[str, Annotated[float, Field(ge=0, le=1e9)]] | None = Field(
        default=None, max_length=64)
    mandatory: list[str] = Field(default_factory=list, max_length=64)
    swath_m: Annotated[float, Field(ge=0.01, le=1e5)] | None = None
    level: int = Field(default=2, ge=1, le=2)


class PlanOut(BaseModel):
    """The best plan (`feasible`) or why there is none (`conflict`, `message`); a feasible
    plan carries its draft `orders`."""

    feasible: bool
    conflict: list[str] | None = None
    message: str | None = None
    reward: Number | None = None
    energy_wh: Number | None = None
    value: Number | None = None
    limit_wh: Number | None = None
    order: list[str] | None = None
    passes: dict[str, int] | None = None
    legs_wh: list[Number] | None = None
    orders: OrdersJson | None = None


@router.post("/missions/{mission_id}/plan-problem", operation_id="planProblemFromMission",
             response_model=PlanProblemJson, **with_limit(allow(*OPERATORS), "plan"))
def plan_problem(mission_id: str, body: ProblemFromMission, db: Db) -> dict[str, Any]:
    """The countersign.plan/1 problem for the mission's areas and vehicle (lawn-mower passes)."""
    orders = orders_from_data(service.get_mission(db, mission_id).draft)
    try:
        problem = problem_from_orders(
            orders, start=body.start, recovery=body.recovery, battery_wh=body.battery_wh,
            reserve_wh=body.reserve_wh, areas=body.areas, rewards=body.rewards,
            mandatory=body.mandatory, swath_m=body.swath_m, level=body.level)
    except CannotBuildProblem as exc:
        raise Unprocessable(str(exc)) from None
    return problem.model_dump(mode="json", exclude_none=True)


@router.post("/plan", operation_id="solvePlan", response_model=PlanOut,
             response_model_exclude_unset=True, **with_limit(allow(*EVERYONE), "plan"))
def solve_plan(body: PlanProblemJson, request: Request,
               principal: CurrentPrincipal) -> dict[str, Any]:
    """The best plan (reward, then energy) and its draft orders, or a minimal conflict."""
    problem = problem_from_data(body)
    slots: PlanSlots = request.app.state.plan_slots
    try:
        with slots.hold(user_key(principal)):
            plan = solve(problem, timeout_s=PLAN_TIMEOUT_S)
    except PlanTooLarge as exc:
        raise Unprocessable(str(exc)) from None
    except PlanTimeout:
        raise Unprocessable(f"no answer within {PLAN_TIMEOUT_S:g} s; use the command "
                            "line (countersign plan --timeout) for large problems") from None
    answer = plan.to_json()
    if plan.feasible:
        answer["orders"] = orders_to_json(orders_from_plan(problem, plan))
    return answer
