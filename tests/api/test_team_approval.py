"""Issue 37 part 2: one approval signs a team's orders, every member's digest inside."""

from __future__ import annotations

import json
from typing import Any

from countersign.approvals.bundle import verify_bundle
from countersign.orders.examples import example_bytes
from countersign.orders.reader import orders_from_data
from countersign.orders.team import member_digests
from countersign.web.routes.schemas import ReportOut

from .approval_helpers import (
    MISSION,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World
from .described import assert_described


def _clean_team() -> dict[str, Any]:
    """The exemplar team with both vehicles always reaching meeting R1: no TEAM error."""
    team: dict[str, Any] = json.loads(example_bytes("search-and-sample-team"))
    team["id"] = MISSION
    team["team"][1]["orders"]["goals"][0]["next"]["violate"] = "G2"
    team["team"][0]["orders"]["goals"][1]["next"]["fail"] = "G4"
    return team


def test_one_approval_signs_every_members_digest(world: World) -> None:
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    team = _clean_team()
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": team},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    report = operator.get(f"/api/missions/{MISSION}/report").json()
    assert report["ok"], report["findings"]
    assert report["team"]["meetings"] == {"R1": ["remus-100", "vehicle-2"]}
    assert report["team"]["joint"]["deadlocked"] == 0
    assert_described(ReportOut, report)

    number = new_version(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = prepare(supervisor, submit(world, number), signer)
    predicate = prepared["statement"]["predicate"]
    expected = member_digests(orders_from_data(team))
    assert predicate["team"] == expected and len(expected) == 2
    submission = prepared["statement"]["predicate"]["submission"]
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": sign_prepared(prepared, signer),
                                     "password": PASSWORD})
    assert response.status_code == 201, response.text
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    assert verify_bundle(bundle).ok


def test_single_vehicle_statements_sign_no_team(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = prepare(supervisor, submit(world, new_version(world)), signer)
    assert "team" not in prepared["statement"]["predicate"]
