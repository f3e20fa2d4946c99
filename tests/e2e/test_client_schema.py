"""The browser app's typed client is generated from frontend/openapi.json; that file must be the
backend's current OpenAPI document, or the client's types describe an API that is gone."""

from __future__ import annotations

import json
from pathlib import Path

from countersign.settings import Settings
from countersign.web.app import create_app

REPO = Path(__file__).resolve().parents[2]


def test_frontend_openapi_document_is_the_backends(tmp_path: Path) -> None:
    settings = Settings(data_dir=tmp_path, database_url=f"sqlite:///{tmp_path / 'api.db'}")
    current = json.loads(json.dumps(create_app(settings).openapi()))
    committed = json.loads((REPO / "frontend" / "openapi.json").read_text(encoding="utf-8"))
    assert committed == current, (
        "frontend/openapi.json differs from the backend's OpenAPI document: run "
        "./scripts/export-openapi --generate (regenerates frontend/src/api/schema.d.ts too), "
        "then ./scripts/build-frontend, and fix any type errors it reports"
    )


def test_every_schema_keeps_its_plain_name() -> None:
    """Two models of one name get module-qualified component names (countersign__web__...),
    which the front end's types would then have to spell: give them distinct names instead."""
    committed = json.loads((REPO / "frontend" / "openapi.json").read_text(encoding="utf-8"))
    qualified = [name for name in committed["components"]["schemas"] if "__" in name]
    assert qualified == [], qualified
