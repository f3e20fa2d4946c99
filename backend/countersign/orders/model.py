"""Typed model of mission orders in the `countersign.orders/1` format.

The model accepts orders that are structurally wrong (no start, a missing outcome, an unknown
target, duplicate ids): those are verification findings, not read errors, so that a supervisor
sees every problem at once. Only input that cannot be a set of orders at all is rejected here.
"""

from __future__ import annotations

import functools
import re
from fractions import Fraction
from typing import Annotated, Any, Final, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    StrictInt,
    field_validator,
    model_validator,
)

from .. import strict_json

FORMAT: Final = "countersign.orders/1"
OUTCOMES: tuple[str, str, str] = ("succeed", "fail", "violate")
Outcome = Literal["succeed", "fail", "violate"]
TerminalKind = Literal["complete", "abort"]

MAX_ID_LENGTH = 100
MAX_TEXT_LENGTH = 10_000
MAX_LIST_LENGTH = 50_000
_ID_PATTERN = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.:\-]*")


def _check_id(value: str) -> str:
    # Ids become IRIs, DOT node names and expression literals: keep them to a safe alphabet.
    if not value:
        raise ValueError("an id must not be empty")
    if len(value) > MAX_ID_LENGTH:
        raise ValueError(f"an id may have at most {MAX_ID_LENGTH} characters")
    if not _ID_PATTERN.fullmatch(value):
        raise ValueError(
            f"{value[:40]!r} is not a valid id: use letters, digits and _ . : - "
            "(starting with a letter, digit or _)"
        )
    return value


Id = Annotated[str, AfterValidator(_check_id)]
Text = Annotated[str, Field(max_length=MAX_TEXT_LENGTH)]
Interval = tuple[float, float]


def _check_envelope(value: dict[str, Interval]) -> dict[str, Interval]:
    for name, (low, high) in value.items():
        _check_id(name)
        if low > high:
            raise ValueError(f"{name}: lower bound {low} is above upper bound {high}")
    return value


Envelope = Annotated[dict[str, Interval], AfterValidator(_check_envelope)]


def _digestible(value: Any) -> Any:
    # Values no field types (params, unknown fields) reach the digest's RFC 8785 form as they
    # are, and it refuses NaN, infinities and integers a double cannot hold: a Turtle
    # "INF"^^xsd:double or 10**30 there was a 500. Typed fields convert or refuse.
    try:
        strict_json.check(value, exact_integers=True)
    except strict_json.JsonPolicyError as exc:
        where = exc.path.removeprefix("$").removeprefix(".")
        raise ValueError(f"{where}: {exc.message}" if where else exc.message) from None
    return value


FreeForm = Annotated[dict[str, Any], AfterValidator(_digestible)]


class _Strict(BaseModel):
    # Unknown fields are kept (they round-trip and are hashed) so newer orders still load.
    model_config = ConfigDict(extra="allow", frozen=True, populate_by_name=True,
                              allow_inf_nan=False)

    @model_validator(mode="after")
    def _digestible_extra(self) -> Any:
        if self.__pydantic_extra__:
            _digestible(self.__pydantic_extra__)
        return self


class Cost(_Strict):
    energy_wh: float | None = Field(default=None, ge=0)
    duration_s: float | None = Field(default=None, ge=0)


@functools.lru_cache(maxsize=4096)
def _exact(value: float) -> Fraction:
    # JSON numbers arrive as floats; their shortest decimal form is what the author wrote, so
    # 0.1 + 0.2 + 0.7 sums to exactly 1.
    return Fraction(repr(float(value)))


ProbabilityValue = Annotated[float, Field(ge=0, le=1)] | tuple[
    Annotated[float, Field(ge=0, le=1)], Annotated[float, Field(ge=0, le=1)]]


class OutcomeProbabilities(_Strict):
    """How likely each outcome of a goal is: a number each (summing to 1) or an interval
    `[lo, hi]` each when only bounds are known (verify.probability computes min and max)."""

    succeed: ProbabilityValue
    fail: ProbabilityValue
    violate: ProbabilityValue

    def bounds(self) -> tuple[tuple[Fraction, Fraction], ...]:
        """Exact (lo, hi) per outcome in the order succeed, fail, violate."""
        result = []
        for outcome in OUTCOMES:
            value = getattr(self, outcome)
            low, high = value if isinstance(value, tuple) else (value, value)
            result.append((_exact(low), _exact(high)))
        return tuple(result)

    @model_validator(mode="after")
    def _sums_to_one(self) -> OutcomeProbabilities:
        bounds = self.bounds()
        for outcome, (low, high) in zip(OUTCOMES, bounds, strict=True):
            if low > high:
                raise ValueError(f"{outcome}: lower bound {float(low)} is above upper bound "
                                 f"{float(high)}")
        if sum(b[0] for b in bounds) > 1 or sum(b[1] for b in bounds) < 1:
            raise ValueError("the probabilities of succeed, fail and violate must sum to 1 "
                             "(or, as intervals, admit a sum of 1)")
        return self


class Budget(_Strict):
    energy_wh: float | None = Field(default=None, ge=0)
    duration_s: float | None = Field(default=None, ge=0)


BUDGET_QUANTITIES: tuple[str, str] = ("energy_wh", "duration_s")


class Goal(_Strict):
    id: Id
    title: Text = ""
    description: Text = ""
    behavior: str | None = None
    # A team's meeting (verify/team.py): every member whose orders name it waits there for
    # the others, and all leave with one shared outcome. Absent outside teams.
    meet: Id | None = None
    area: Id | None = None
    requires: list[Id] = Field(default_factory=list, max_length=1000)
    envelope: Envelope = Field(default_factory=dict)
    params: FreeForm = Field(default_factory=dict)
    # A list names several successors for one outcome: a G5 finding, possible from Turtle/AVCL.
    next: dict[Outcome, Id | list[Id] | None] = Field(default_factory=dict)
    cost: Cost | None = None
    # Outcome probabilities (absent: taken from the vehicle's profile for the behaviour, else
    # unknown, so only bounds follow).
    p: OutcomeProbabilities | None = None
    # Progressive refinement (seed 000 III.D): sub-orders that carry the goal out (absent: none,
    # so orders without it keep their canonical JSON and digest).
    refines: Refinement | None = None

    @property
    def label(self) -> str:
        return self.title or self.id

    def successors(self, outcome: str) -> list[str]:
        """Every target named for an outcome (empty when none is named)."""
        target = self.next.get(outcome)  # type: ignore[call-overload]
        if target is None:
            return []
        if isinstance(target, str):
            return [target]
        return list(dict.fromkeys(target))


class Terminal(_Strict):
    id: Id
    kind: TerminalKind
    title: Text = ""

    @property
    def label(self) -> str:
        return self.title or ("Mission complete" if self.kind == "complete" else "Mission abort")


class RefinementTerminal(Terminal):
    """The end of a refinement: `returns` names the parent goal's outcome. Typed loosely so that
    a missing or unknown outcome is a REFINE finding (verify.refine), not a read error."""

    returns: Annotated[str, Field(max_length=MAX_ID_LENGTH)] | None = None


MAX_REFINEMENT_STEPS = 10_000


class RefinementBound(_Strict):
    """The time-out of a refinement with a loop (verify.refine defines the unrolling): a goal
    inside commences only while fewer than `steps` goals have commenced, or while the goals
    that ended inside took less than `duration_s` seconds."""

    steps: int | None = Field(default=None, ge=1, le=MAX_REFINEMENT_STEPS)
    duration_s: float | None = Field(default=None, gt=0)

    @model_validator(mode="after")
    def _one_bound(self) -> RefinementBound:
        if (self.steps is None) == (self.duration_s is None):
            raise ValueError("a time-out gives exactly one of steps or duration_s")
        return self


DIGEST_PATTERN = r"^sha256:[0-9a-f]{64}$"
MAX_PROCEDURE_VERSION = 1_000_000


class Refinement(_Strict):
    """Sub-orders that carry out a goal: ids inside are local (outside they read G1/G1.1).

    A refinement may instead name a procedure of the library (verify/procedures.py): name,
    version and the digest it pins; the body is copied in from the library before checking,
    and a body that does not have the pinned digest is a PROCEDURE finding."""

    procedure: Id | None = None
    version: StrictInt | None = Field(default=None, ge=1, le=MAX_PROCEDURE_VERSION)
    digest: Annotated[str, Field(pattern=DIGEST_PATTERN)] | None = None
    start: Id | list[Id] | None = None
    goals: list[Goal] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    terminals: list[RefinementTerminal] = Field(default_factory=list,
                                                max_length=MAX_LIST_LENGTH)
    within: RefinementBound | None = None
    on_timeout: Literal["fail", "violate"] | None = None

    @model_validator(mode="after")
    def _reference(self) -> Refinement:
        if self.procedure is None and (self.version is not None or self.digest is not None):
            raise ValueError("version and digest belong to a procedure reference: "
                             "name the procedure too")
        if self.procedure is not None and self.version is None:
            raise ValueError(f"the reference to procedure {self.procedure!r} names no version")
        return self


Goal.model_rebuild()


DEFAULT_TERMINALS: tuple[Terminal, ...] = (
    Terminal(id="COMPLETE", kind="complete", title="Mission complete"),
    Terminal(id="ABORT", kind="abort", title="Mission abort"),
)


class Constraint(_Strict):
    id: Id
    text: Text = ""
    applies_to: Literal["mission"] | list[Id] = "mission"
    expr: Text | None = None


class Norm(_Strict):
    id: Id
    context: Text
    forbidden: Text | None = None
    obligated: Text | None = None
    permitted: Text | None = None
    text: Text = ""

    @model_validator(mode="after")
    def _one_modality(self) -> Norm:
        given = [m for m in ("forbidden", "obligated", "permitted") if getattr(self, m)]
        if len(given) != 1:
            raise ValueError("a norm names exactly one of forbidden, obligated or permitted")
        return self


class Area(_Strict):
    id: Id
    title: Text = ""
    polygon: list[tuple[float, float]] = Field(default_factory=list, max_length=10_000)
    contexts: list[str] = Field(default_factory=list, max_length=100)

    @field_validator("polygon")
    @classmethod
    def _lat_lon(cls, value: list[tuple[float, float]]) -> list[tuple[float, float]]:
        for index, (lat, lon) in enumerate(value):
            if not (-90 <= lat <= 90 and -180 <= lon <= 180):
                raise ValueError(f"point {index} ({lat}, {lon}) is not a latitude/longitude")
        return value


ChartKind = Literal["protected_area", "shipping_lane", "traffic_separation", "keep_out",
                   "anchorage", "land", "other"]


class ChartNorm(_Strict):
    """A norm a chart carries for its own area: `forbidden` is an expression over `behavior`
    (a leg between goals is behaviour 'transit'), e.g. `behavior == 'transit'`."""

    id: Id
    forbidden: Text
    text: Text = ""


class Chart(Area):
    """A shared area from the server's chart registry, copied into the orders it was checked
    with so that the digest (and an approval) covers it (verify/geo.py reads it)."""

    kind: ChartKind = "other"
    norms: list[ChartNorm] = Field(default_factory=list, max_length=100)


class Quantity(_Strict):
    unit: str = ""
    type: Literal["real", "integer", "boolean"] = "real"
    min: float | None = None
    max: float | None = None
    title: Text = ""


class Feature(_Strict):
    id: Id
    title: Text = ""
    fulfills: list[Id] = Field(default_factory=list)
    measures: list[Id] = Field(default_factory=list)
    # Constraints the feature is asserted to test (MEO canTest, NPS canMeasure): honoured by M6
    # when the constraint's condition did not survive (NPS Turtle carries no expressions).
    tests: list[Id] = Field(default_factory=list)


RuleKind = Literal["observation", "estimation", "goal", "safety", "action"]
MAX_LITERAL_LENGTH = 200


class _AliasedRule(_Strict):
    # `if` is a Python keyword: the field is `if_` but reads and writes as "if" everywhere.
    model_config = ConfigDict(
        extra="allow", frozen=True, populate_by_name=True, serialize_by_alias=True,
        allow_inf_nan=False,
    )


class RuleFact(_Strict):
    """An observed or static fact of a default theory (seed 004 W_obs)."""

    id: Id
    fact: Annotated[str, Field(max_length=MAX_LITERAL_LENGTH)]
    text: Text = ""


class StrictRule(_AliasedRule):
    """`if` literals imply `then` (seed 004 W_est, W_goal, W_safety); exceptions are these."""

    id: Id
    kind: RuleKind = "estimation"
    if_: list[Annotated[str, Field(max_length=MAX_LITERAL_LENGTH)]] = Field(
        default_factory=list, alias="if", max_length=100
    )
    then: Annotated[str, Field(max_length=MAX_LITERAL_LENGTH)]
    exception_to: list[Id] = Field(default_factory=list, max_length=100)
    text: Text = ""


class DefaultRule(_AliasedRule):
    """A normal default `if : then / then` (seed 004 D_est, D_goal, D_safety)."""

    id: Id
    kind: RuleKind = "estimation"
    if_: list[Annotated[str, Field(max_length=MAX_LITERAL_LENGTH)]] = Field(
        default_factory=list, alias="if", max_length=100
    )
    then: Annotated[str, Field(max_length=MAX_LITERAL_LENGTH)]
    priority: int = 0
    text: Text = ""


class RuleSet(_Strict):
    """A normal default theory carried by orders or a vehicle profile (countersign.rules reads it).

    Typed here only structurally: the literal syntax is checked by `countersign.rules.parse_theory`
    and reported as RULES findings, so a typo in a rule never makes the orders unreadable.
    """

    observables: list[Annotated[str, Field(max_length=MAX_LITERAL_LENGTH)]] = Field(
        default_factory=list, max_length=10_000
    )
    actions: list[Id] = Field(default_factory=list, max_length=10_000)
    facts: list[RuleFact] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    strict: list[StrictRule] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    defaults: list[DefaultRule] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)


MAX_SPEED_MPS = 1000.0
# The team check explores the product of the members' MEAs: keep the factors few.
MAX_TEAM_MEMBERS = 8


class Vehicle(_Strict):
    id: Id
    title: Text = ""
    envelope: Envelope = Field(default_factory=dict)
    features: list[Feature] = Field(default_factory=list, max_length=1000)
    behaviors: list[str] = Field(default_factory=list, max_length=1000)
    # Bounded to what flies or sails (about Mach 3): 1e308 overflowed the rehearsal's clock.
    speed_mps: float | None = Field(default=None, gt=0, le=MAX_SPEED_MPS)
    power_w: float | None = Field(default=None, ge=0)
    budget: Budget | None = None
    # Contingency rules of the vehicle itself (absent: no field, so digests are unchanged).
    rules: RuleSet | None = None
    # Outcome probabilities per behaviour, for goals that give none themselves.
    p: dict[str, OutcomeProbabilities] | None = None


class Event(_Strict):
    """What happens at one position of a path: a goal ending with an outcome, or the terminal.
    Every field given must match (a list: any of its items)."""

    goal: Id | list[Id] | None = None
    outcome: Outcome | list[Outcome] | None = None
    behavior: str | list[str] | None = None
    terminal: Id | list[Id] | None = None
    kind: TerminalKind | None = None


PatternKind = Literal["absence", "existence", "universality", "precedence", "response",
                      "bounded_response"]
ScopeKind = Literal["globally", "before", "after", "between"]


class Within(_Strict):
    """The bound of a bounded response, from the moment p happens (its goal ends) to the moment
    s happens: goals ended, or seconds or watt-hours of the goals and legs in between."""

    steps: int | None = Field(default=None, ge=0)
    duration_s: float | None = Field(default=None, ge=0)
    energy_wh: float | None = Field(default=None, ge=0)


class PathProperty(_Strict):
    id: Id
    always: Text | None = None
    never: Text | None = None
    text: Text = ""
    # A temporal specification pattern (Dwyer et al.) over every path (verify.patterns):
    # `p` and `s` are its events, `q` and `r` open and close its scope.
    pattern: PatternKind | None = None
    scope: ScopeKind = "globally"
    p: Event | None = None
    s: Event | None = None
    q: Event | None = None
    r: Event | None = None
    within: Within | None = None


class Orders(_Strict):
    format: Literal["countersign.orders/1"] = FORMAT
    id: Id
    title: Text = ""
    description: Text = ""
    vehicle: Id | None = None
    # A list is how Turtle input says "two starts"; M1 reports it.
    start: Id | list[Id] | None = None
    goals: list[Goal] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    terminals: list[Terminal] | None = Field(default=None, max_length=MAX_LIST_LENGTH)
    constraints: list[Constraint] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    norms: list[Norm] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    areas: list[Area] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    # Registry charts in use; absent from orders that predate charts.
    charts: list[Chart] = Field(default_factory=list, max_length=MAX_LIST_LENGTH)
    quantities: dict[str, Quantity] = Field(default_factory=dict)
    vehicles: list[Vehicle] = Field(default_factory=list, max_length=1000)
    properties: list[PathProperty] = Field(default_factory=list, max_length=1000)
    # Contingency rules for this mission (seed 004), merged with the vehicle profile's.
    rules: RuleSet | None = None
    # One MEA per vehicle instead of goals here (orders/team.py); absent: one vehicle.
    team: list[TeamMember] | None = Field(default=None, min_length=2,
                                          max_length=MAX_TEAM_MEMBERS)

    @model_validator(mode="after")
    def _team_alone(self) -> Orders:
        if self.team is not None:
            check_team(self)
        return self

    @property
    def effective_terminals(self) -> list[Terminal]:
        return list(DEFAULT_TERMINALS) if self.terminals is None else list(self.terminals)

    def target_vehicle(self) -> Vehicle | None:
        for vehicle in self.vehicles:
            if vehicle.id == self.vehicle:
                return vehicle
        return self.vehicles[0] if self.vehicle is None and len(self.vehicles) == 1 else None

    def goal_index(self) -> dict[str, Goal]:
        """Goals by id; the first definition wins when ids repeat (DUP reports the rest)."""
        index: dict[str, Goal] = {}
        for goal in self.goals:
            index.setdefault(goal.id, goal)
        return index

    def terminal_index(self) -> dict[str, Terminal]:
        index: dict[str, Terminal] = {}
        for terminal in self.effective_terminals:
            index.setdefault(terminal.id, terminal)
        return index

    def area_index(self) -> dict[str, Area]:
        index: dict[str, Area] = {}
        for area in self.areas:
            index.setdefault(area.id, area)
        return index


def declares_probabilities(orders: Orders) -> bool:
    """Whether any goal or vehicle gives outcome probabilities (verify.probability's input)."""
    return any(g.p is not None for g in orders.goals) or any(
        v.p for v in orders.vehicles)


class TeamMember(_Strict):
    """One vehicle of a team with its own orders (its goals, profile, budget and norms)."""

    vehicle: Id
    orders: Orders = Field(description="the member vehicle's own countersign.orders/1 orders "
                                       "(no team)")

    @model_validator(mode="before")
    @classmethod
    def _orders_name_vehicle(cls, data: Any) -> Any:
        # A member's orders target the member's vehicle: filled in when absent, so that the
        # member's own checks (M7, BUDGET, NORM) read its profile.
        if isinstance(data, dict) and isinstance(data.get("orders"), dict) \
                and "vehicle" not in data["orders"] and "team" not in data["orders"] \
                and isinstance(data.get("vehicle"), str):
            data = {**data, "orders": {**data["orders"], "vehicle": data["vehicle"]}}
        return data


def check_team(orders: Orders) -> None:
    """Read errors for a team that cannot be a team (what can be checked is a finding)."""
    # Late import: orders/team.py reads the model.
    from .team import team_read_problems

    problem = team_read_problems(orders)
    if problem is not None:
        raise ValueError(problem)


Orders.model_rebuild()
