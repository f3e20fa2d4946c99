"""Procedures: a refinement saved by name and integer version, used by reference.

A procedure document reads

    {"format": "countersign.procedure/1", "name": "recovery-drill", "version": 2,
     "refines": {"start": "R1", "goals": [...], "terminals": [...], "within": ..., ...}}

and its digest is `sha256:` over the RFC 8785 JSON of exactly those four members (format, name,
version, the refinement as written). A goal uses it with `"refines": {"procedure":
"recovery-drill", "version": 2, "digest": "sha256:..."}`; the orders' canonical JSON contains
that reference, so the orders' digest covers the procedure's digest. Before checking, the body
is copied in beside the reference (verify/procedures.py), and a body whose digest is not the
pinned one is a PROCEDURE finding, so a changed procedure never passes as the one named.
"""

from __future__ import annotations

import hashlib
from typing import Any, Final, Literal

import rfc8785
from pydantic import BaseModel, ConfigDict, Field, StrictInt, ValidationError, model_validator

from .. import strict_json
from .model import MAX_PROCEDURE_VERSION, Id, Refinement
from .reader import OrdersReadError, Problem, problems_from_validation

PROCEDURE_FORMAT: Final = "countersign.procedure/1"
MAX_PROCEDURE_BYTES = 2 * 1024 * 1024
MAX_PROCEDURE_GOALS = 2000
REFERENCE_FIELDS: Final = frozenset({"procedure", "version", "digest"})
BODY_FIELDS: Final = frozenset({"start", "goals", "terminals", "within", "on_timeout"})


class Procedure(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    format: Literal["countersign.procedure/1"] = PROCEDURE_FORMAT
    name: Id
    version: StrictInt = Field(ge=1, le=MAX_PROCEDURE_VERSION)
    refines: Refinement

    @model_validator(mode="after")
    def _a_body(self) -> Procedure:
        if self.refines.procedure is not None:
            raise ValueError("a procedure's refines is its own refinement (start, goals, "
                             "terminals), not a reference to another procedure")
        if not self.refines.goals:
            raise ValueError("a procedure's refinement has no goals")
        if _goal_count(self.refines) > MAX_PROCEDURE_GOALS:
            raise ValueError(f"a procedure has at most {MAX_PROCEDURE_GOALS} goals at all its "
                             "levels together")
        return self

    @property
    def digest(self) -> str:
        return procedure_digest(self.name, self.version, self.refines)

    def reference(self) -> dict[str, Any]:
        return {"procedure": self.name, "version": self.version, "digest": self.digest}

    def to_json(self) -> dict[str, Any]:
        return {"format": PROCEDURE_FORMAT, "name": self.name, "version": self.version,
                "refines": body_json(self.refines)}


def _goal_count(refinement: Refinement, depth: int = 0) -> int:
    if depth > 64:  # deeper than any refinement REFINE accepts: count it as too large
        return MAX_PROCEDURE_GOALS + 1
    return sum(1 + (_goal_count(g.refines, depth + 1) if g.refines is not None else 0)
               for g in refinement.goals)


def has_body(refinement: Refinement) -> bool:
    return bool(refinement.model_fields_set & BODY_FIELDS)


def body_json(refinement: Refinement) -> dict[str, Any]:
    """The refinement as written, without the reference fields."""
    data: dict[str, Any] = refinement.model_dump(mode="json", exclude_unset=True)
    for key in REFERENCE_FIELDS:
        data.pop(key, None)
    return data


def procedure_digest(name: str, version: int, refinement: Refinement) -> str:
    document: dict[str, Any] = {"format": PROCEDURE_FORMAT, "name": name, "version": version,
                "refines": body_json(refinement)}
    return "sha256:" + hashlib.sha256(bytes(rfc8785.dumps(document))).hexdigest()


def procedure_from_data(data: Any) -> Procedure:
    if not isinstance(data, dict):
        raise OrdersReadError([Problem("$", "a procedure must be a JSON object")])
    if data.get("format") != PROCEDURE_FORMAT:
        raise OrdersReadError([Problem("$.format", f"format must be '{PROCEDURE_FORMAT}'")])
    try:
        return Procedure.model_validate(data)
    except ValidationError as exc:
        raise problems_from_validation(exc) from None


def read_procedure(data: bytes) -> Procedure:
    """A procedure document from bytes; OrdersReadError names what is wrong and where."""
    if len(data) > MAX_PROCEDURE_BYTES:
        raise OrdersReadError([Problem("$", f"a procedure has at most {MAX_PROCEDURE_BYTES} "
                                            "bytes")])
    try:
        parsed = strict_json.loads(data)
    except strict_json.JsonPolicyError as exc:
        raise OrdersReadError([Problem(exc.path, exc.message)]) from None
    except (ValueError, UnicodeDecodeError):
        raise OrdersReadError([Problem("$", "a procedure is a JSON document")]) from None
    return procedure_from_data(parsed)
