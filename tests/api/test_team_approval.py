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
    # The printable approval document holds the team's plain orders, meetings side by side.
    document = world.client("auditor").get(
        f"/api/missions/{MISSION}/versions/{number}/document.txt")
    assert document.status_code == 200, document.text
    assert "Meeting points" in document.text and "Vehicle 2 of 2: vehicle-2" in document.text
    assert f"Member vehicle-2: orders digest {expected['vehicle-2']}" in document.text


def test_single_vehicle_statements_sign_no_team(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = prepare(supervisor, submit(world, new_version(world)), signer)
    assert "team" not in prepared["statement"]["predicate"]


def test_team_orders_are_never_a_500(world: World) -> None:
    operator = world.client("operator")
    team = _clean_team()
    validated = operator.post("/api/validate", json=team)
    assert validated.status_code == 200, validated.text
    assert validated.json()["team"]["joint"]["count"] == validated.json()["paths"]["count"]
    mission = operator.get(f"/api/missions/{MISSION}")
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": team},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    number = new_version(world)
    supervisor = world.client("supervisor")
    for path in (f"/api/missions/{MISSION}/versions/{number}/review",
                 f"/api/missions/{MISSION}/paths",
                 f"/api/missions/{MISSION}/standing"):
        response = supervisor.get(path)
        assert response.status_code < 500, (path, response.status_code, response.text)
    # What reads one vehicle's MEA (vehicle files, simulations) refuses a team, never a 500
    # (campaigns run teams: tests/api/test_team_campaigns.py).
    for path in (f"/api/missions/{MISSION}/versions/{number}/vehicle/imc",
                 f"/api/missions/{MISSION}/versions/{number}/vehicle/moos"):
        response = operator.get(path)
        assert 400 <= response.status_code < 500, (path, response.status_code, response.text)
    for path, body in ((f"/api/missions/{MISSION}/rehearsals", {"version": number}),):
        response = operator.post(path, json=body)
        assert 400 <= response.status_code < 500, (path, response.status_code, response.text)
    paths = supervisor.get(f"/api/missions/{MISSION}/paths")
    assert paths.status_code == 409 and "team" in paths.json()["detail"]


def test_the_registry_profile_of_each_member_is_copied_in(world: World) -> None:
    team = _clean_team()
    profile = team["team"][1]["orders"].pop("vehicles")[0]
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    before = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": team},
                          headers={"If-Match": mission.headers["ETag"]})
    assert before.status_code == 200, before.text
    report = operator.get(f"/api/missions/{MISSION}/report").json()
    assert "vehicle-2/vehicle-2" in {s for f in report["findings"] if f["code"] == "VEHICLE"
                                     for s in f["subjects"]}
    assert world.client("admin").put("/api/vehicles/vehicle-2", json=profile).status_code == 200
    mission = operator.get(f"/api/missions/{MISSION}")
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": team},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    draft = operator.get(f"/api/missions/{MISSION}").json()["orders"]
    assert draft["team"][1]["orders"]["vehicles"][0]["id"] == "vehicle-2"
    assert operator.get(f"/api/missions/{MISSION}/report").json()["ok"]
