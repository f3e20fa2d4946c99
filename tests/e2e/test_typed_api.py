"""The typed API end to end: every JSON route names its response model, and
the browser's role table (frontend/src/roles.gen.ts) is the routes' x-roles, regenerated."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from countersign.settings import Settings
from countersign.web.app import create_app
from countersign.web.roles_ts import operation_roles, roles_typescript

REPO = Path(__file__).resolve().parents[2]
# Answers that are not one JSON document of a model: a map of names (health).
UNTYPED = {"health"}


@pytest.fixture(scope="module")
def document(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    data = tmp_path_factory.mktemp("openapi")
    settings = Settings(data_dir=data, database_url=f"sqlite:///{data / 'api.db'}")
    return create_app(settings).openapi()


def _named(schema: dict[str, Any]) -> bool:
    if schema.get("type") == "array":
        return _named(schema.get("items", {}))
    parts = schema.get("allOf") or schema.get("anyOf") or [schema]
    return all("$ref" in part for part in parts)


def test_every_json_route_names_its_response_model(document: dict[str, Any]) -> None:
    untyped = []
    for path, operations in document["paths"].items():
        for method, operation in operations.items():
            for status, response in operation["responses"].items():
                schema = response.get("content", {}).get("application/json", {}).get("schema")
                if (status.startswith("2") and schema is not None
                        and operation["operationId"] not in UNTYPED and not _named(schema)):
                    untyped.append(f"{method.upper()} {path} ({operation['operationId']})")
    assert not untyped, f"routes answering JSON without a named response model: {untyped}"


def test_orders_are_documented_by_the_pydantic_model(document: dict[str, Any]) -> None:
    schemas = document["components"]["schemas"]
    assert schemas["Orders"]["title"] == "Orders"
    for model in ("MissionDetail", "ReviewOut", "ApprovalDetailOut", "VersionOut"):
        refs = str(schemas[model]["properties"]["orders"])
        assert "#/components/schemas/Orders" in refs, model


def test_the_browsers_role_table_is_the_servers(document: dict[str, Any]) -> None:
    committed = (REPO / "frontend" / "src" / "roles.gen.ts").read_text(encoding="utf-8")
    assert committed == roles_typescript(document), (
        "frontend/src/roles.gen.ts differs from the routes' x-roles: run "
        "./scripts/export-openapi --generate")


def test_the_role_table_lists_every_operation(document: dict[str, Any]) -> None:
    table = operation_roles(document)
    assert table["createMission"] == ["operator"]
    assert table["listEvents"] == ["supervisor", "auditor", "admin"]
    assert len(table) == sum(len(ops) for ops in document["paths"].values())
