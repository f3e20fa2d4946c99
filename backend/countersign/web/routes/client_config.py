"""What the browser app needs to know of the server's configuration (map tiles, for now)."""

from __future__ import annotations

from fastapi import APIRouter, Request
from pydantic import BaseModel, Field

from ..deps import EVERYONE, allow

router = APIRouter(prefix="/api", tags=["system"])


class ClientConfigOut(BaseModel):
    map_tiles: str | None = Field(description=(
        "URL template of the map tiles under the plan view ({z}/{x}/{y}, Web Mercator, 256 "
        "pixels), or null: no tiles, the plan view is drawn offline"))
    map_tiles_attribution: str = Field(description="text to show beside the tiles")


@router.get("/client-config", operation_id="getClientConfig", response_model=ClientConfigOut,
            **allow(*EVERYONE))
def client_config(request: Request) -> ClientConfigOut:
    settings = request.app.state.settings
    return ClientConfigOut(map_tiles=settings.map_tiles,
                           map_tiles_attribution=settings.map_tiles_attribution)
