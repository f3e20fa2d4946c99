"""The shapes of a live rehearsal's status (rehearse/manager.py, Rehearsal.status) and of a
stored rehearsal record (countersign.rehearsal/1, Rehearsal._record_json), for OpenAPI.

Both are handed over untouched (SchemaOf): a record is hashed as stored, so re-validating it
could only change what its digest covers; these models only document it for the front end's
generated types. tests/web/test_rehearsals.py checks that they describe the answers exactly."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, Field

from .schemas import Number, SchemaOf


class SimEvent(BaseModel):
    """One event of the simulation at simulated second `t`; `data` depends on its kind."""

    t: Number
    kind: str
    text: str
    goal: str | None = None
    data: dict[str, Any] | None = None
    # A team's rehearsal (rehearse/team.py): the vehicle whose event it is.
    vehicle: str | None = None


class CurrentGoal(BaseModel):
    id: str
    title: str
    behavior: str | None
    area: str | None
    progress: Number


class GoalOutcome(BaseModel):
    goal: str
    outcome: str


class FaultNotice(BaseModel):
    """What injecting a fault did: applied at once, or queued while a goal waits."""

    fault: str
    text: str
    state: Literal["queued", "applied"]


class Suggestion(BaseModel):
    outcome: str
    because: str


class TeamMemberStatus(BaseModel):
    """One vehicle of a team's rehearsal: `waiting` holds at a meeting for its partners,
    `deadlocked` was left waiting for a partner that can no longer come (TEAM)."""

    vehicle: str
    state: Literal["running", "waiting", "finished", "deadlocked"]
    current_goal: CurrentGoal | None
    outcomes: list[GoalOutcome]
    terminal: str | None
    energy_wh: Number
    energy_used_wh: Number
    capacity_wh: Number
    sim_time_s: Number


class TeamMeeting(BaseModel):
    """A meeting that happened: its one shared outcome, and each vehicle's goal there."""

    meet: str
    t: Number
    outcome: str
    reason: str
    goals: dict[str, str]


class TeamStatus(BaseModel):
    members: list[TeamMemberStatus]
    meetings: list[TeamMeeting]
    # Where each member ended once the team's rehearsal has finished
    # (`remus-100:waiting + vehicle-2:ABORT`, as the TEAM joint counts name it).
    joint_end: str | None


class GoalRef(BaseModel):
    id: str
    title: str


class RefinementTimeout(BaseModel):
    """A refinement's time-out ended it (`within`): the refined goal, the outcome it returned
    and the simulated second."""

    goal: str
    title: str
    returns: str
    t: Number


class RefinedStatus(BaseModel):
    """A refined mission's rehearsal: the refined goals the current goal runs inside,
    outermost first (the breadcrumb G1 › G1.2), and the last time-out that ended one."""

    inside: list[GoalRef]
    timeout: RefinementTimeout | None


class RehearsalStatus(BaseModel):
    id: str
    state: Literal["running", "waiting_for_outcome", "finished", "stopped"]
    source: Literal["manual", "replay", "tour", "simulate"]
    seed: int
    path_index: int | None
    run: int
    current_goal: CurrentGoal | None
    step: int
    outcomes: list[GoalOutcome]
    terminal: str | None
    energy_wh: Number
    energy_used_wh: Number
    capacity_wh: Number
    sim_time_s: Number
    speed: Number | None
    pace: Literal["auto", "fixed"]
    skipping: bool
    frames: int
    first_question_frame: int | None
    faults: list[str]
    queued_faults: list[str]
    fault_notice: FaultNotice | None
    events: list[SimEvent]
    port: int
    # Only while a goal waits for its outcome.
    question: str | None = None
    suggested: Suggestion | None = None
    # Only for a team's orders: every vehicle, the meetings and the joint end.
    team: TeamStatus | None = None
    # Only for orders with refinements.
    refined: RefinedStatus | None = None


class RecordOrders(BaseModel):
    id: str
    digest: str


class RecordOptions(BaseModel):
    source: str
    seed: int
    path_index: int | None
    faults: list[str]


class Choice(BaseModel):
    t: Number
    goal: str
    outcome: str


class RecordInputs(BaseModel):
    faults: list[str]
    choices: list[Choice]


class RecordRun(BaseModel):
    path_index: int | None
    goals: list[str]
    outcomes: list[str]
    terminal: str | None
    terminal_kind: str | None


class RecordEnergy(BaseModel):
    capacity_wh: Number
    used_wh: Number
    remaining_wh: Number


class FlownLeg(BaseModel):
    from_: str = Field(alias="from")
    outcome: str
    to: str
    length_m: Number
    planned_m: Number


class RecordWorld(BaseModel):
    recovery: tuple[Number, Number]
    generated_lane: bool
    contacts: int


class TeamRecordEnergy(BaseModel):
    capacity_wh: Number
    used_wh: Number


class TeamRecordInputs(BaseModel):
    faults: list[str]


class TeamRecordMember(BaseModel):
    """One vehicle of a team's record: its own run fields as a one-vehicle record holds them
    (its events are the record's events naming it). Records made before these fields existed
    (2026-12-04) lack them."""

    vehicle: str
    state: Literal["running", "waiting", "finished", "deadlocked"]
    orders: RecordOrders | None = None
    goals: list[str] = []
    outcomes: list[str] = []
    terminal: str | None = None
    terminal_kind: str | None = None
    steps: int = 0
    legs_flown: list[FlownLeg] = []
    unmonitored_constraints: list[str] = []
    runs: list[RecordRun]
    energy: TeamRecordEnergy
    sim_time_s: Number
    inputs: TeamRecordInputs
    rule_firings: dict[str, int]


class TeamRecord(BaseModel):
    """A team's rehearsal: each vehicle's own figures, the meetings, the joint end and the
    paths replayed by vehicle (the top-level figures are the team's together)."""

    vehicles: list[str]
    joint_end: str
    meetings: list[TeamMeeting]
    members: list[TeamRecordMember]
    paths: dict[str, int]


class RehearsalRecordOut(BaseModel):
    """A rehearsal record: what the rehearsal determined, and nothing that would change its
    digest between two runs of the same orders, seed and inputs."""

    format: Literal["countersign.rehearsal/1"]
    orders: RecordOrders
    options: RecordOptions
    seed: int
    state: Literal["finished", "stopped_early"]
    inputs: RecordInputs
    runs: list[RecordRun]
    goals: list[str]
    outcomes: list[str]
    terminal: str | None
    terminal_kind: str | None
    sim_time_s: Number
    steps: int
    events: list[SimEvent]
    events_dropped: int
    rule_firings: dict[str, int]
    rules: bool
    energy: RecordEnergy
    unmonitored_constraints: list[str]
    # Records made before the legs were recorded (2026-12-02) lack it.
    legs_flown: list[FlownLeg] = []
    world: RecordWorld
    # Only for a team's orders.
    team: TeamRecord | None = None


RehearsalStatusJson = Annotated[dict[str, Any], SchemaOf(RehearsalStatus)]
RehearsalRecordJson = Annotated[dict[str, Any], SchemaOf(RehearsalRecordOut)]
