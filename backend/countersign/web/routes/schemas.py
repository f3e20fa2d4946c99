"""Response models shared by the routes."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    GetCoreSchemaHandler,
    GetJsonSchemaHandler,
    RootModel,
)
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import CoreSchema
from pydantic_core import core_schema as cs

from ...orders.model import Orders, Vehicle
from ...plan.model import PlanProblem
from ...store.event_words import event_change
from ...store.tables import Event, MissionVersion, User


class SchemaOf:
    """A JSON object passed through untouched (stored orders keep their exact bytes, ints stay
    ints) but documented in OpenAPI by `model`'s schema, so the front end's types come from the
    Pydantic model rather than a hand-written copy."""

    def __init__(self, model: type[BaseModel]) -> None:
        self.model = model

    def __get_pydantic_core_schema__(self, source: Any, handler: GetCoreSchemaHandler
                                     ) -> CoreSchema:
        return cs.dict_schema(keys_schema=cs.str_schema(), values_schema=cs.any_schema())

    def __get_pydantic_json_schema__(self, schema: CoreSchema, handler: GetJsonSchemaHandler
                                     ) -> JsonSchemaValue:
        # A bare $ref would be resolved and inlined by pydantic; as a list item it stays a
        # named component, and allOf keeps it one.
        item = handler(cs.list_schema(self.model.__pydantic_core_schema__))["items"]
        return {"allOf": [item]}


OrdersJson = Annotated[dict[str, Any], SchemaOf(Orders)]
VehicleJson = Annotated[dict[str, Any], SchemaOf(Vehicle)]
PlanProblemJson = Annotated[dict[str, Any], SchemaOf(PlanProblem)]
# Numbers as the server computed them: an int stays an int (a `float` field would add ".0").
Number = int | float


class RequestBody(BaseModel):
    """Request bodies refuse fields they do not know: a typo is an error, not a silent no-op."""

    model_config = ConfigDict(extra="forbid")


class UserOut(BaseModel):
    id: int
    username: str
    display_name: str
    role: str
    disabled: bool = False

    @classmethod
    def of(cls, user: User) -> UserOut:
        return cls(id=user.id, username=user.username, display_name=user.display_name,
                   role=user.role, disabled=user.disabled)


class VersionOut(BaseModel):
    number: int
    digest: str
    author: str
    created_at: datetime
    orders: OrdersJson | None = None


class FindingOut(BaseModel):
    code: str
    severity: str
    subjects: list[str]
    message: str
    details: dict[str, Any] | None = None


# A finding as its check wrote it (orders/findings.py, Finding.to_json): `details` only when set.
FindingJson = Annotated[dict[str, Any], SchemaOf(FindingOut)]


class LayoutPoint(BaseModel):
    x: Number
    y: Number


class Layout(RootModel[dict[str, LayoutPoint]]):
    """The graph editor's node positions, by node id: editor data kept beside the orders."""


LayoutJson = Annotated[dict[str, Any], SchemaOf(Layout)]


class PathCountsOut(BaseModel):
    count: int
    by_terminal: dict[str, int]


class CostPathOut(BaseModel):
    goals: list[str]
    outcomes: list[str]
    terminal: str


class WorstCostOut(BaseModel):
    worst: float
    budget: float | None
    path: CostPathOut | None
    unknown_cost: list[str] = []
    estimated_cost: list[str] = []


class BoundOut(BaseModel):
    """A probability or an expectation as [min, max] (equal when the orders pin it down)."""

    min: Number
    max: Number


class ExpectationOut(BoundOut):
    quantiles: dict[str, Number] | None
    unknown_cost: list[str]


class ProbabilitiesOut(BaseModel):
    """Outcome probabilities (verify/probability.py, Probabilities.to_json): terminals, some
    violation, expected costs; `unknown` goals have no probabilities, `intervals` goals only
    intervals, and `exact` is neither."""

    exact: bool
    terminals: dict[str, BoundOut]
    violation: BoundOut
    expected: dict[str, ExpectationOut]
    unknown: list[str]
    intervals: list[str]


ProbabilitiesJson = Annotated[dict[str, Any], SchemaOf(ProbabilitiesOut)]


class TeamMemberOut(BaseModel):
    """One member of a team: its own orders' figures (verify/team_report.py)."""

    vehicle: str
    mission: str
    digest: str
    ok: bool
    paths: PathCountsOut | None
    costs: dict[str, WorstCostOut] | None
    probabilities: ProbabilitiesOut | None = None


class JointEndsOut(BaseModel):
    """How many joint executions end with each member at the terminal `ends` names (null:
    left waiting at a meeting)."""

    ends: dict[str, str | None]
    count: int


class JointWaitingOut(BaseModel):
    """How many joint executions leave `vehicle` waiting at `meeting` for ever."""

    meeting: str
    vehicle: str
    count: int


class JointCountsOut(BaseModel):
    count: int
    deadlocked: int
    by_ends: list[JointEndsOut]
    waiting: list[JointWaitingOut]


class TeamOut(BaseModel):
    """Orders with a team (verify/team.py): members, meetings and joint executions."""

    members: list[TeamMemberOut]
    meetings: dict[str, list[str]]
    joint: JointCountsOut | None


class ReportOut(BaseModel):
    """The validation report: every check that exists (docs/api.md, Reports)."""

    mission: str
    digest: str
    ok: bool
    findings: list[FindingOut]
    paths: PathCountsOut | None
    costs: dict[str, WorstCostOut] | None = None
    probabilities: ProbabilitiesOut | None = Field(default=None, description=(
        "only for orders that declare probabilities"))
    team: TeamOut | None = Field(default=None, description=(
        "only for orders with a team; `paths` then counts joint executions"))
    checker: str = Field(description=(
        "the fingerprint of the checks and ontology that made the report (sha256: and 64 hex "
        "digits); a stored report made by other checks is never answered, it is recomputed"))


class MissionPathOut(BaseModel):
    index: int
    goals: list[str]
    outcomes: list[str]
    terminal: str
    # The path's probability, or [min, max]; absent when the orders declare no probabilities.
    probability: float | tuple[float, float] | None = None


class PathPage(BaseModel):
    count: int
    by_terminal: dict[str, int]
    # With a goal or terminal search: how many paths match (`count` stays the total).
    matching: int | None = None
    items: list[MissionPathOut]
    next_cursor: str | None


class MissionSummary(BaseModel):
    id: str
    title: str
    vehicle: str | None
    status: str = Field(description="the status the log gives the mission (draft, submitted, "
                        "withdrawn, approved, rejected, revoked), not the table's copy")
    draft_digest: str
    revision: int
    latest_version: int | None
    ok: bool | None
    errors: int | None
    warnings: int | None
    updated_at: datetime
    updated_by: str
    integrity: list[str] = Field(default_factory=list, description=(
        "how the tables disagree with the log about this mission's status (a row changed "
        "behind the app's back); empty when they agree"))


class MissionDetail(MissionSummary):
    orders: OrdersJson
    layout: LayoutJson
    versions: list[VersionOut]
    import_findings: list[FindingJson] = []


class MissionPage(BaseModel):
    items: list[MissionSummary]
    next_cursor: str | None


class EventOut(BaseModel):
    id: int
    at: datetime
    actor: str | None
    kind: str
    mission: str | None
    before_digest: str | None
    after_digest: str | None
    detail: dict[str, Any]
    integrity: list[str] = Field(default_factory=list, description=(
        "how this row disagrees with its log entry, which is the source of truth"))
    index: int | None = Field(default=None, description=(
        "this event's entry in the transparency log (None: its entry is missing)"))
    target: str | None = Field(default=None, description="what the event is about")
    change: str = Field(default="", description="what changed, in words")

    @classmethod
    def of(cls, event: Event, actor: str | None, integrity: list[str] | None = None,
           index: int | None = None) -> EventOut:
        return cls(id=event.id, at=event.at, actor=actor, kind=event.kind,
                   mission=event.mission_id, before_digest=event.before_digest,
                   after_digest=event.after_digest, detail=event.detail,
                   integrity=integrity or [], index=index, target=event.target,
                   change=event_change(event.kind, event.mission_id, event.detail or {}))


def version_out(version: MissionVersion, author: str, with_orders: bool) -> VersionOut:
    return VersionOut(number=version.number, digest=version.digest, author=author,
                      created_at=version.created_at,
                      orders=version.orders if with_orders else None)
