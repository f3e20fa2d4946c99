"""The FastAPI application factory."""

from __future__ import annotations

from fastapi import FastAPI

from .. import __version__
from .settings import Settings


def create_app(settings: Settings) -> FastAPI:
    app = FastAPI(title="Countersign", version=__version__, docs_url="/api/docs",
                  openapi_url="/api/openapi.json")
    app.state.settings = settings

    @app.get("/api/health", operation_id="health", tags=["system"])
    def health() -> dict[str, str]:
        """Liveness: the app answers and knows its version."""
        return {"status": "ok", "version": __version__}

    return app
