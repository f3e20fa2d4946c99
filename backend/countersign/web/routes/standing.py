"""GET /api/missions/{id}/standing: the latest approved version and the latest decision."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path
from pydantic import BaseModel

from ...store.missions import get_mission
from ...store.standing import mission_standing
from ..deps import EVERYONE, Db, TransactionRoute, allow

router = APIRouter(prefix="/api", tags=["missions"], route_class=TransactionRoute)


class StandingDecisionOut(BaseModel):
    """A decision on the standing (named apart from the approvals' DecisionOut, so that both
    keep plain names in the OpenAPI document and so in the generated types)."""

    version: int
    decision: str
    record: int


class StandingOut(BaseModel):
    approved: StandingDecisionOut | None
    latest: StandingDecisionOut | None


@router.get("/missions/{mission_id}/standing", operation_id="getMissionStanding",
            response_model=StandingOut, **allow(*EVERYONE))
def get_standing(mission_id: Annotated[str, Path(max_length=100)], db: Db) -> StandingOut:
    get_mission(db, mission_id)  # 404 for a mission that does not exist
    standing = mission_standing(db, mission_id)

    def out(decision: object) -> StandingDecisionOut | None:
        return None if decision is None else StandingDecisionOut.model_validate(decision,
                                                                        from_attributes=True)

    return StandingOut(approved=out(standing.approved), latest=out(standing.latest))
