"""Rehearsal campaigns: start one on a stored version, follow its progress, cancel
it, read its estimates, take its per-goal probabilities as suggestions, attach its record to a
submission.

Who may do what: operators and supervisors start campaigns and cancel their own; every role
reads them. A person may have MAX_ACTIVE_PER_USER campaigns queued or running (429 beyond).
On SQLite the app runs the jobs in its own threads (and resumes unfinished campaigns when it
starts); on PostgreSQL it queues them for `countersign campaign worker` processes.
"""

from __future__ import annotations

import threading
from datetime import datetime
from typing import Annotated, Any

from fastapi import APIRouter, FastAPI, Path, Query, Request
from pydantic import BaseModel, Field

from ...campaigns.spec import AT_START, MAX_SEED, MAX_SIMULATIONS, NO_FAULT, CampaignSpec
from ...campaigns.stats import goal_probabilities
from ...campaigns.team import sweep_fault_reach
from ...errors import Forbidden, NotFound
from ...jobs import CampaignRunner, runner_for
from ...orders.reader import orders_from_data
from ...store import approvals as approvals_service
from ...store import campaigns as store
from ...store.missions import get_mission, get_version
from ..deps import EVERYONE, CurrentPrincipal, Db, RowId, Services, TransactionRoute, allow
from .campaign_schemas import CampaignResultsJson, CampaignSpecJson, OfferedProbabilitiesJson
from .schemas import RequestBody

router = APIRouter(prefix="/api", tags=["campaigns"], route_class=TransactionRoute)
STARTERS = ("operator", "supervisor")
CampaignId = Annotated[str, Path(min_length=16, max_length=16, pattern=r"^[0-9a-f]{16}$")]
SweepName = Annotated[str, Field(min_length=1, max_length=100,
                                 pattern=r"^[A-Za-z0-9_.:-]{1,100}$")]
_runner_lock = threading.Lock()


class CampaignIn(RequestBody):
    simulations: int = Field(ge=1, le=MAX_SIMULATIONS)
    faults: list[SweepName] = Field(default_factory=lambda: [NO_FAULT], max_length=8,
                                    description="faults of the sweep; 'none' for no fault")
    goals: list[SweepName] = Field(default_factory=lambda: [AT_START], max_length=32,
                                   description="goals at whose start the faults are injected; "
                                   "'start' for the start of the mission")
    seed: int = Field(default=0, ge=0, le=MAX_SEED)


class CampaignOut(BaseModel):
    id: str
    mission: str | None
    version: int | None
    orders_digest: str
    owner: str | None
    spec: CampaignSpecJson
    simulations: int
    done: int
    state: str
    created_at: datetime
    ended_at: datetime | None
    digest: str | None
    error: str | None
    results: CampaignResultsJson | None


class AttachCampaignIn(RequestBody):
    campaign: str = Field(min_length=16, max_length=16, pattern=r"^[0-9a-f]{16}$")


class AttachedCampaignOut(BaseModel):
    submission: int
    campaign: str
    digest: str


def start_runner(app: FastAPI) -> CampaignRunner:
    """The app's runner, made once (and then resuming unfinished SQLite campaigns)."""
    with _runner_lock:
        runner: CampaignRunner | None = getattr(app.state, "campaign_runner", None)
        if runner is None:
            runner = runner_for(app.state.database)
            app.state.campaign_runner = runner
            resume = getattr(runner, "resume", None)
            if resume is not None:
                resume()
        return runner


def runner_of(request: Request) -> CampaignRunner:
    return start_runner(request.app)


@router.post("/missions/{mission_id}/versions/{number}/campaigns", operation_id="startCampaign",
             status_code=201, response_model=CampaignOut, **allow(*STARTERS))
def start_campaign(mission_id: str, number: RowId,
                   body: CampaignIn, request: Request, principal: CurrentPrincipal,
                   db: Db, services: Services) -> CampaignOut:
    """Queue N seeded simulations of this version over the sweep faults x goals. A team's
    simulations run every member (faults `VEHICLE:FAULT` for one member) and its results are
    the joint ends, meetings and member terminals (`results.team`)."""
    stored = get_version(db, mission_id, number)
    orders = orders_from_data(stored.orders)
    spec = CampaignSpec.build(simulations=body.simulations, faults=body.faults,
                              goals=body.goals, seed=body.seed, orders=orders)
    row = store.create(db, orders=stored.orders, orders_digest=stored.digest,
                       spec=spec.to_json(), simulations=spec.simulations, owner=principal.user,
                       mission_id=mission_id, version=number, signer=services.signer)
    out = CampaignOut(**store.summary(db, row))
    db.commit()  # the jobs read the campaign from their own sessions
    runner_of(request).enqueue(row.id, spec.chunks())
    return out


class FaultReachOut(BaseModel):
    fault: str
    reacts: bool
    because: str


@router.get("/missions/{mission_id}/versions/{number}/fault-reach", operation_id="faultReach",
            response_model=list[FaultReachOut], **allow(*EVERYONE))
def get_fault_reach(mission_id: str, number: RowId, db: Db,
                    fault: Annotated[list[SweepName], Query(max_length=16)]) -> list[FaultReachOut]:
    """Whether each simulated fault can change an outcome of this version (a constraint or
    contingency rule reads what it changes, or the vehicle reacts to it): said before a campaign
    runs, so a sweep of a fault nothing reacts to is not read as evidence."""
    orders = orders_from_data(get_version(db, mission_id, number).orders)
    return [FaultReachOut(fault=r.fault, reacts=r.reacts, because=r.because)
            for r in sweep_fault_reach(orders, fault)]


@router.get("/missions/{mission_id}/campaigns", operation_id="listCampaigns",
            response_model=list[CampaignOut], **allow(*EVERYONE))
def list_campaigns(mission_id: str, db: Db,
                   limit: Annotated[int, Query(ge=1, le=200)] = 50) -> list[CampaignOut]:
    get_mission(db, mission_id)
    return [CampaignOut(**store.summary(db, row))
            for row in store.list_for_mission(db, mission_id, limit=limit)]


@router.get("/campaigns/{campaign_id}", operation_id="getCampaign", response_model=CampaignOut,
            **allow(*EVERYONE))
def get_campaign(campaign_id: CampaignId, db: Db) -> CampaignOut:
    """Progress (`done` of `simulations`) and, once finished, the estimates."""
    return CampaignOut(**store.summary(db, store.get(db, campaign_id)))


@router.post("/campaigns/{campaign_id}/cancel", operation_id="cancelCampaign",
             response_model=CampaignOut, **allow(*STARTERS))
def cancel_campaign(campaign_id: CampaignId, principal: CurrentPrincipal,
                    db: Db, services: Services) -> CampaignOut:
    """Stop a queued or running campaign of yours; what was simulated stays stored."""
    row = store.get(db, campaign_id)
    if row.owner_id != principal.user.id:
        raise Forbidden("only the person who started a campaign can cancel it")
    return CampaignOut(**store.summary(db, store.cancel(db, campaign_id, actor=principal.user,
                                                        signer=services.signer)))


class CampaignProbabilitiesOut(BaseModel):
    campaign: str
    digest: str | None
    orders_digest: str
    goals: dict[str, OfferedProbabilitiesJson]


@router.get("/campaigns/{campaign_id}/probabilities", operation_id="campaignProbabilities",
            response_model=CampaignProbabilitiesOut, **allow(*EVERYONE))
def campaign_probabilities(campaign_id: CampaignId, db: Db) -> dict[str, Any]:
    """Per-goal outcome probabilities estimated by a finished campaign, in the orders' `p`
    form (point estimates and 95% intervals): suggestions for the operator to copy into a new
    draft. Nothing is written into any orders here."""
    row = store.get(db, campaign_id)
    record = store.sealed_record(row)
    if row.state != "finished" or not record:
        raise NotFound(f"campaign {campaign_id} is {row.state}: no estimates yet")
    return {"campaign": row.id, "digest": row.digest, "orders_digest": row.orders_digest,
            "goals": goal_probabilities(record["results"])}


@router.post("/submissions/{submission_id}/campaigns", operation_id="attachCampaign",
             status_code=201, response_model=AttachedCampaignOut, **allow("operator"))
def attach_campaign(submission_id: RowId,
                    body: AttachCampaignIn, principal: CurrentPrincipal,
                    db: Db, services: Services) -> AttachedCampaignOut:
    """Cite a finished campaign of exactly the submitted version (409 otherwise); only the
    submitting operator, only while the submission awaits a decision."""
    submission = approvals_service.get_submission(db, submission_id)
    if submission.submitted_by != principal.user.id:
        raise Forbidden("only the operator who submitted it can attach a campaign")
    store.attach(db, submission=submission, campaign_id=body.campaign, actor=principal.user,
                 signer=services.signer)
    row = store.get(db, body.campaign)
    assert row.digest is not None
    return AttachedCampaignOut(submission=submission_id, campaign=row.id, digest=row.digest)


@router.get("/submissions/{submission_id}/campaigns", operation_id="listAttachedCampaigns",
            response_model=list[AttachedCampaignOut], **allow(*EVERYONE))
def list_attached_campaigns(submission_id: RowId,
                            db: Db) -> list[AttachedCampaignOut]:
    approvals_service.get_submission(db, submission_id)
    return [AttachedCampaignOut(submission=a.submission_id, campaign=a.campaign_id,
                                digest=a.digest) for a in store.attached(db, submission_id)]
