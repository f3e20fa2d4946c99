"""Witness cosignatures: a witness (`countersign witness`) posts its cosignature of a checkpoint
it verified; the server keeps those by registered witnesses and publishes them."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request
from pydantic import Field

from ...services.log_signer import signer_directory
from ...store import approvals as service
from ...store.cosignatures import add_cosignature, cosignature_lines
from ..deps import EVERYONE, LOG_READERS, Db, Services, TransactionRoute, allow
from .approval_schemas import CosignatureOut, CosignedCheckpointOut
from .schemas import RequestBody

router = APIRouter(prefix="/api", tags=["approvals"], route_class=TransactionRoute)


class CosignatureIn(RequestBody):
    checkpoint: str = Field(min_length=1, max_length=1000,
                            description="the checkpoint body the witness cosigned")
    cosignature: str = Field(min_length=1, max_length=1000,
                             description="its C2SP tlog-cosignature line")


@router.post("/log/cosignatures", operation_id="addCosignature", status_code=201,
             response_model=CosignatureOut, **allow(*LOG_READERS))
def post_cosignature(body: CosignatureIn, db: Db, request: Request) -> dict[str, Any]:
    """Accept a registered witness's cosignature of a checkpoint the log signed."""
    row = add_cosignature(db, directory=signer_directory(request.app.state.settings),
                          body=body.checkpoint, line=body.cosignature)
    return {"size": row.tree_size, "witness": row.witness, "cosignature": row.line}


@router.get("/log/cosigned", operation_id="getCosignedCheckpoint",
            response_model=CosignedCheckpointOut, **allow(*EVERYONE))
def get_cosigned(db: Db, services: Services) -> dict[str, Any]:
    """The latest checkpoint with the witnesses' cosignature lines appended to its note."""
    row = service.latest_checkpoint(db, signer=services.signer)
    plain = service.checkpoint_json(row)
    lines = cosignature_lines(db, plain["note"])
    return {**service.checkpoint_json(row, lines), "cosignatures": lines}
