"""The shapes of a campaign's stored results (campaigns/stats.py builds them), for OpenAPI.

Results are stored records handed over untouched (SchemaOf), so these models document the
answer for the front end's generated types without re-validating what the runner wrote."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, RootModel

from .schemas import Number, SchemaOf


class CampaignSpecOut(BaseModel):
    """What a campaign simulates (campaigns/spec.py, CampaignSpec.to_json): the sweep is
    faults x goals, and simulation i runs cell i mod cells with seed seed + i div cells."""

    simulations: int
    faults: list[str]
    goals: list[str]
    seed: int
    chunk: int


class Estimate(BaseModel):
    """A count among the simulations, its proportion and 95% Wilson interval."""

    count: int
    p: Number | None
    ci: tuple[Number, Number]


class GoalEstimate(BaseModel):
    visits: int
    succeed: Estimate
    fail: Estimate
    violate: Estimate


class CoveredPath(BaseModel):
    path: int
    count: int


class Coverage(BaseModel):
    total_paths: int | None
    covered: int
    paths: list[CoveredPath]


class Histogram(BaseModel):
    edges: list[Number]
    counts: list[int]


class EnergySummary(BaseModel):
    mean: Number | None
    min: Number | None
    max: Number | None
    histogram: Histogram


class CampaignResults(BaseModel):
    simulations: int
    terminals: dict[str, Estimate]
    kinds: dict[str, Estimate]
    no_terminal: Estimate
    any_violation: Estimate
    goals: dict[str, GoalEstimate]
    coverage: Coverage
    energy_wh: EnergySummary


class JointEndRow(BaseModel):
    """Runs that ended in one joint end (`remus-100:waiting + vehicle-2:ABORT`), and whether
    the verifier's joint counts have it (`executions`: how many joint executions end there;
    both null when the verifier could not count them)."""

    end: str
    count: int
    p: Number | None
    ci: tuple[Number, Number]
    possible: bool | None
    executions: int | None


class MeetingRow(BaseModel):
    meet: str
    vehicles: list[str]
    completed: Estimate
    deadlocked: Estimate
    outcomes: dict[str, int]


class MemberRow(BaseModel):
    """A member's terminals over the runs ('waiting': left waiting at a meeting; 'none': a
    bound stopped it)."""

    vehicle: str
    terminals: dict[str, Estimate]
    total_paths: int | None
    covered_paths: int


class JointCoverage(BaseModel):
    checked: bool
    possible: int | None
    reached: int
    missed: list[str]


class JointFinding(BaseModel):
    """Runs that ended in a joint end the verifier says no joint execution reaches."""

    code: Literal["TEAM"]
    severity: Literal["error"]
    end: str
    count: int
    runs: list[int]
    message: str


class TeamCampaignSummary(BaseModel):
    vehicles: list[str]
    joint: list[JointEndRow]
    unfinished: Estimate
    meetings: list[MeetingRow]
    members: list[MemberRow]
    coverage: JointCoverage
    findings: list[JointFinding]


class TeamCampaignResults(BaseModel):
    """A team campaign's results (campaigns/team_stats.py)."""

    simulations: int
    team: TeamCampaignSummary


class AnyCampaignResults(RootModel[CampaignResults | TeamCampaignResults]):
    """One vehicle's campaign results, or a team's (with `team`)."""


class CampaignOrders(BaseModel):
    id: str
    digest: str


class CampaignRecord(BaseModel):
    """A finished campaign's record (jobs/tasks.py, campaign_record): what an approval cites by
    the digest of its RFC 8785 form."""

    format: Literal["countersign.campaign/1"]
    orders: CampaignOrders
    spec: CampaignSpecOut
    results: AnyCampaignResults


class OfferedProbabilities(BaseModel):
    """A goal's outcome probabilities offered from a campaign: point estimates and intervals."""

    visits: int
    point: dict[str, Number]
    interval: dict[str, tuple[Number, Number]]


CampaignSpecJson = Annotated[dict[str, Any], SchemaOf(CampaignSpecOut)]
CampaignResultsJson = Annotated[dict[str, Any], SchemaOf(AnyCampaignResults)]
CampaignRecordJson = Annotated[dict[str, Any], SchemaOf(CampaignRecord)]
OfferedProbabilitiesJson = Annotated[dict[str, Any], SchemaOf(OfferedProbabilities)]
