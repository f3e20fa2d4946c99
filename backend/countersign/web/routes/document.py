"""GET /api/missions/{id}/versions/{n}/document: the printable approval document, as
sections for the page to print, and as one text (`document.txt`)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path
from fastapi.responses import PlainTextResponse
from pydantic import BaseModel, Field

from ...approvals.document import text
from ...store.approval_document import version_document
from ..deps import EVERYONE, Db, RowId, Services, TransactionRoute, allow

MissionId = Annotated[str, Path(max_length=100)]
router = APIRouter(prefix="/api", tags=["approvals"], route_class=TransactionRoute)


class SectionOut(BaseModel):
    heading: str
    text: str


class DocumentOut(BaseModel):
    mission: str
    version: int
    digest: str
    sections: list[SectionOut] = Field(description=(
        "in reading order; 'Plain-language orders' is what `countersign export --format "
        "plain` writes"))
    text: str = Field(description="the whole document as one text")


@router.get("/missions/{mission_id}/versions/{number}/document", operation_id="getDocument",
            response_model=DocumentOut, **allow(*EVERYONE))
def get_document(mission_id: MissionId, number: RowId, db: Db,
                 services: Services) -> DocumentOut:
    """Digest, plain orders with their checked conditions, findings, path counts by terminal,
    the rehearsal summary, the decision, its signer and key fingerprint."""
    version, sections = version_document(db, mission_id, number, reports=services.reports)
    return DocumentOut(mission=mission_id, version=number, digest=version.digest,
                       sections=[SectionOut(heading=s.heading, text=s.text) for s in sections],
                       text=text(sections))


@router.get("/missions/{mission_id}/versions/{number}/document.txt",
            operation_id="getDocumentText", response_class=PlainTextResponse,
            **allow(*EVERYONE))
def get_document_text(mission_id: MissionId, number: RowId, db: Db,
                      services: Services) -> PlainTextResponse:
    """The same document as one text file."""
    _, sections = version_document(db, mission_id, number, reports=services.reports)
    return PlainTextResponse(text(sections), headers={
        "Content-Disposition": f'attachment; filename="{mission_id}-v{number}-approval.txt"'})
