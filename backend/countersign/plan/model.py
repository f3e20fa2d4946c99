"""The survey planning problem `countersign.plan/1` (seed 001, GRAVITAS section 5 and 8).

Coordinates are metres in a local frame. Energy of a plan = the sum of its transit legs
(start -> entry of the first area, exit -> entry between areas, last exit -> recovery), each
Euclidean distance x `transit_wh_per_m`, plus the `survey_wh` of each chosen pass. A plan is
feasible when its energy is at most `battery_wh - reserve_wh` and it surveys every mandatory
area. Level 1 uses each area's first pass; level 2 chooses one pass per area.

Input that cannot be a problem raises `PlanReadError` (an `OrdersReadError`, so every caller
that already reports unreadable orders reports it the same way) with JSON paths.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Final, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, model_validator
from pydantic_core import ErrorDetails

from ..orders.model import Id, Text
from ..orders.reader import (
    OrdersReadError,
    json_data,
    location_path,
    read_limited,
    refuse_size,
    validated,
)

FORMAT: Final = "countersign.plan/1"
MAX_AREAS: Final = 64  # the model's bound; the exact solver has its own, smaller, state bound
MAX_PASSES: Final = 16
MAX_COORDINATE_M: Final = 1e8


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise ValueError("must be a finite number")
    return value


def _point(value: tuple[float, float]) -> tuple[float, float]:
    for coordinate in value:
        if not math.isfinite(coordinate) or abs(coordinate) > MAX_COORDINATE_M:
            raise ValueError(
                f"coordinates must be finite metres within +-{MAX_COORDINATE_M:g} of the origin"
            )
    return value


Point = Annotated[tuple[float, float], AfterValidator(_point)]
Amount = Annotated[float, Field(ge=0), AfterValidator(_finite)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class PlanVehicle(_Model):
    transit_wh_per_m: Amount
    battery_wh: Amount
    reserve_wh: Amount = 0.0

    @property
    def limit_wh(self) -> float:
        """Energy a plan may use: the battery less the reserve."""
        return self.battery_wh - self.reserve_wh


class Pass(_Model):
    entry: Point
    exit: Point
    survey_wh: Amount
    title: Text = ""


class PlanArea(_Model):
    id: Id
    title: Text = ""
    reward: Amount
    mandatory: bool = False
    passes: list[Pass] = Field(min_length=1, max_length=MAX_PASSES)

    @property
    def label(self) -> str:
        return self.title or self.id


class Conversion(_Model):
    """A conversion function to the common currency of the rewards (seed 001 section 5.3):
    linear `rate * x`, or exponential `scale * (exp(rate * x) - 1)`, x the amount used."""

    kind: Literal["linear", "exponential"] = "linear"
    rate: Amount
    scale: Amount = 1.0

    def value(self, amount: float) -> float:
        if self.kind == "linear":
            return self.rate * amount
        try:
            return self.scale * math.expm1(self.rate * amount)
        except OverflowError:
            return math.inf


class PlanProblem(_Model):
    format: Literal["countersign.plan/1"] = FORMAT
    level: Literal[1, 2] = 2
    start: Point
    recovery: Point
    vehicle: PlanVehicle
    areas: list[PlanArea] = Field(default_factory=list, max_length=MAX_AREAS)
    # With a conversion, the best plan maximises reward less the converted energy (then uses
    # the least energy); without one, reward first and energy second.
    conversion: dict[Literal["energy_wh"], Conversion] = Field(default_factory=dict)

    def objective(self, reward: float, energy_wh: float) -> float:
        energy = self.conversion.get("energy_wh")
        return reward if energy is None else reward - energy.value(energy_wh)

    @model_validator(mode="after")
    def _distinct_ids(self) -> PlanProblem:
        seen: set[str] = set()
        for area in self.areas:
            if area.id in seen:
                raise ValueError(f"two areas have the id {area.id!r}")
            seen.add(area.id)
        return self

    def passes_of(self, area: PlanArea) -> list[Pass]:
        """The passes the solver may choose from: only the first at level 1."""
        return area.passes[:1] if self.level == 1 else list(area.passes)


class PlanReadError(OrdersReadError):
    """Input that cannot be read as a planning problem (or a plan); `problems` say where."""


def _reword(err: ErrorDetails, path: str, message: str) -> tuple[str, str]:
    if err["type"] == "literal_error" and path == "$.format":
        message = f"format must be {FORMAT!r}"
    elif err["type"] == "literal_error" and path == "$.level":
        message = "level must be 1 (order only) or 2 (order and passes)"
    elif err["type"] == "missing" and isinstance(err["loc"][-1], int):
        path = location_path(tuple(err["loc"])[:-1])
        message = "a point is two numbers [x, y] in metres"
    elif err["type"] == "too_long" and path.endswith(("start", "recovery", "entry", "exit")):
        message = "a point is two numbers [x, y] in metres"
    elif err["type"] == "extra_forbidden":
        message = "unknown field (check its spelling)"
    return path, message


def problem_from_data(data: Any) -> PlanProblem:
    return validated(PlanProblem, data, what="a planning problem", error=PlanReadError,
                     reword=_reword)


def json_from_bytes(data: bytes, name: str = "<input>") -> Any:
    """Parsed JSON, or a `PlanReadError` that says what is wrong and where."""
    refuse_size(data, name, PlanReadError)
    return json_data(data, PlanReadError)


def read_bytes(data: bytes, name: str = "<input>") -> PlanProblem:
    return problem_from_data(json_from_bytes(data, name))


def read_path_bytes(path: str | Path) -> bytes:
    return read_limited(path, PlanReadError)


def read_file(path: str | Path) -> PlanProblem:
    return read_bytes(read_path_bytes(path), str(path))
