"""OpenAPI links: which response carries the ids that other operations take.

A client (or a stateful fuzzer such as schemathesis) reads them to follow a mission from the
list to its versions, submissions and approvals with ids the server handed out, instead of
guessing ids that only ever reach a 404. One table, added to the generated document, so route
modules stay as they are."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from fastapi import FastAPI

# Runtime expressions (OpenAPI 3.1, "Runtime Expressions"). A JSON pointer names one item of
# a list (the first): the standard has no wildcard.
FIRST_MISSION = "$response.body#/items/0/id"
MISSION = "$response.body#/id"
MISSION_OF_VERSION = "$request.path.mission_id"
VERSION = "$response.body#/number"
LATEST_VERSION = "$response.body#/latest_version"

_MISSION_TARGETS = ("getMission", "getReport", "listPaths", "exportMission", "createVersion",
                    "getMissionStanding", "listRehearsalRecords", "planProblemFromMission")
_VERSION_TARGETS = ("getVersion", "reviewVersion", "submitVersion", "downloadPackage",
                    "recordExecution")
_SUBMISSION_TARGETS = ("getSubmission", "prepareDecision", "withdrawSubmission",
                       "attachRehearsal")
_APPROVAL_TARGETS = ("getApproval", "prepareRevocation")


def _to(targets: tuple[str, ...], parameters: dict[str, str]) -> dict[str, dict[str, Any]]:
    return {target: {"operationId": target, "parameters": parameters} for target in targets}


# (source operationId, status) -> link name -> link object
LINKS: dict[tuple[str, str], dict[str, dict[str, Any]]] = {
    ("listMissions", "200"): _to(_MISSION_TARGETS, {"mission_id": FIRST_MISSION}),
    ("createMission", "201"): _to(_MISSION_TARGETS, {"mission_id": MISSION}),
    ("importMission", "201"): _to(_MISSION_TARGETS, {"mission_id": MISSION}),
    ("getMission", "200"): _to(_VERSION_TARGETS, {"mission_id": MISSION,
                                                  "number": LATEST_VERSION}),
    ("createVersion", "201"): _to(_VERSION_TARGETS, {"mission_id": MISSION_OF_VERSION,
                                                     "number": VERSION}),
    ("listSubmissions", "200"): {
        **_to(_SUBMISSION_TARGETS, {"submission_id": "$response.body#/0/id"}),
        **_to(("getVersion", "reviewVersion"), {"mission_id": "$response.body#/0/mission",
                                                "number": "$response.body#/0/version"})},
    ("submitVersion", "201"): _to(_SUBMISSION_TARGETS, {"submission_id": "$response.body#/id"}),
    ("getSubmission", "200"): _to(("getVersion", "reviewVersion"), {
        "mission_id": "$response.body#/mission", "number": "$response.body#/version"}),
    ("listApprovals", "200"): _to(_APPROVAL_TARGETS, {"approval_id": "$response.body#/items/0/id"}),
    ("signDecision", "201"): _to(_APPROVAL_TARGETS, {"approval_id": "$response.body#/id"}),
    ("listKeys", "200"): _to(("revokeKey",), {"key_id": "$response.body#/0/key_id"}),
}


def add_links(document: dict[str, Any]) -> dict[str, Any]:
    """Put LINKS into the responses of a generated OpenAPI document (in place); a link whose
    source or target operation is missing is an error, so the table cannot drift silently."""
    operations = {operation["operationId"]: operation
                  for path in document["paths"].values() for operation in path.values()
                  if isinstance(operation, dict) and "operationId" in operation}
    for (source, status), links in LINKS.items():
        missing = [name for name in (source, *links) if name not in operations]
        if missing:
            raise ValueError(f"OpenAPI links name unknown operations: {missing}")
        response = operations[source]["responses"][status]
        response["links"] = {**response.get("links", {}), **links}
    return document


def install(app: FastAPI) -> None:
    generate: Callable[[], dict[str, Any]] = app.openapi

    def openapi_with_links() -> dict[str, Any]:
        if app.openapi_schema is None:  # FastAPI's generator caches its document there
            app.openapi_schema = add_links(generate())
        return app.openapi_schema

    app.openapi = openapi_with_links  # type: ignore[method-assign]
