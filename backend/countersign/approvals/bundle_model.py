"""The audit bundle's shape (`countersign.audit-bundle/1`): what GET /api/audit/bundle sends and
what `countersign audit verify` and the browser's verifier read.

Pydantic models, because the API documents the bundle with them (web/routes/approval_schemas.py
subclasses `Bundle` as BundleOut to document the orders and records it passes through), and the
OpenAPI document names each component by its class: the names end in "Out" for that reason.
The offline verifier reads a bundle through `Bundle.from_json`, so a bundle missing a part is
refused naming the part rather than read half-way."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BaseModel, ValidationError, WithJsonSchema

from ..orders.json_fields import Malformed

BUNDLE_FORMAT = "countersign.audit-bundle/1"


class CheckpointOut(BaseModel):
    size: int
    root: str
    note: str
    signed_note: str
    origin: str
    key_id: str
    public_key: str
    signature: str
    created_at: str


class BundleKeyOut(BaseModel):
    key_id: str
    public_key: str
    user: str | None
    created_at: str
    revoked_at: str | None


class LogKeyOut(BaseModel):
    key_id: str
    public_key: str
    origin: str
    verifier_key: str


# A served bundle (200) gives every approval its log entry; the bundle inside the 409 problem
# for a log with deleted entries has null where an entry is gone, and the verifier reports it.
# The API documents the 200 response, so the schema stays an integer.
LogIndex = Annotated[int | None, WithJsonSchema({"type": "integer"})]


class BundleInclusionOut(BaseModel):
    index: LogIndex
    size: int
    hashes: list[str]


class BundleApprovalOut(BaseModel):
    id: int
    mission: str
    decision: str
    log_index: LogIndex
    envelope: str
    inclusion: BundleInclusionOut


class Bundle(BaseModel):
    """An audit bundle for `countersign audit verify BUNDLE` (DESIGN.md, approval record)."""

    format: str
    created_at: str
    scope: str | None
    log_key: LogKeyOut
    entries: list[str]
    receipts: list[str | None]
    signer_refused: str | None
    checkpoints: list[CheckpointOut]
    keys: list[BundleKeyOut]
    # Passed through as stored: the orders by digest, the cited records by digest.
    orders: dict[str, dict[str, Any]]
    approvals: list[BundleApprovalOut]
    rehearsals: dict[str, dict[str, Any]]
    campaigns: dict[str, dict[str, Any]] = {}

    @classmethod
    def from_json(cls, data: Any) -> Bundle:
        """The bundle in this JSON; Malformed names the first part that is not as the format
        says (e.g. `approvals[0].envelope`)."""
        if not isinstance(data, dict) or data.get("format") != BUNDLE_FORMAT:
            raise Malformed(f"not an audit bundle (format {BUNDLE_FORMAT} expected)")
        try:
            return cls.model_validate(_filled(data), strict=True)
        except ValidationError as exc:
            error = exc.errors()[0]
            where = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in error["loc"])
            raise Malformed(f"the bundle's {where.lstrip('.')} is not as the format says: "
                            f"{error['msg']}") from None

    def to_json(self) -> dict[str, Any]:
        """The bundle as served: the fields set, in the format's order."""
        # The small parts (keys, checkpoints, approvals) through pydantic; the orders and
        # records passed through are JSON already and are handed on as they are, not walked
        # (model_dump walks every value of a 14 MB bundle: 0.4 s against a few ms).
        data: dict[str, Any] = {}
        for name in type(self).model_fields:
            if name in self.model_fields_set:
                data[name] = _dumped(getattr(self, name))
        return data


def _dumped(value: Any) -> Any:
    if isinstance(value, BaseModel):
        return value.model_dump(exclude_unset=True)
    if isinstance(value, list):
        return [_dumped(v) for v in value]
    return value


# What an absent part of a bundle reads as: the parts the format gained over time (a bundle
# exported before them lacks them) and the parts that add nothing to a check are optional to
# a reader, as they always were; what a check needs (entries, checkpoints, envelopes) is not.
_ABSENT: dict[str, Any] = {
    "created_at": "", "scope": None, "entries": [], "receipts": [], "signer_refused": None,
    "checkpoints": [], "keys": [], "orders": {}, "approvals": [], "rehearsals": {},
    "campaigns": {}}
_ABSENT_LOG_KEY = {"key_id": "", "origin": "", "verifier_key": ""}
_ABSENT_CHECKPOINT = {"created_at": ""}


def _filled(data: dict[str, Any]) -> dict[str, Any]:
    """The bundle with its absent optional parts as empty ones (a copy; the parts given are
    not changed)."""
    filled = {**_ABSENT, **data}
    if isinstance(filled.get("log_key"), dict):
        filled["log_key"] = {**_ABSENT_LOG_KEY, **filled["log_key"]}
    if isinstance(filled["checkpoints"], list):
        filled["checkpoints"] = [{**_ABSENT_CHECKPOINT, **c} if isinstance(c, dict) else c
                                 for c in filled["checkpoints"]]
    if isinstance(filled["approvals"], list):
        filled["approvals"] = [_filled_approval(a) if isinstance(a, dict) else a
                               for a in filled["approvals"]]
    return filled


def _filled_approval(approval: dict[str, Any]) -> dict[str, Any]:
    # An approval without an inclusion proof is read as one that proves nothing (size -1
    # names no checkpoint), so the verifier reports it rather than refusing the bundle.
    return {"mission": "", "decision": "",
            "inclusion": {"index": approval.get("log_index"), "size": -1, "hashes": []},
            **approval}
