"""One approval signs a team's orders, every member's digest inside."""

from __future__ import annotations

import json
import time
from typing import Any

from countersign.approvals.bundle import verify_bundle
from countersign.orders.examples import example_bytes
from countersign.orders.reader import orders_from_data
from countersign.orders.team import member_digests
from countersign.web.routes.schemas import ReportOut

from .approval_helpers import (
    MISSION,
    approve,
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
    # (campaigns run teams: tests/web/test_team_campaigns.py).
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


def test_an_approved_team_is_packaged_with_every_members_vehicle_files(world: World) -> None:
    """The package of an approved team holds each member's vehicle files (`vehicle/MEMBER.NAME`),
    their digests are what the statement signs, and both package verifiers accept it."""
    import hashlib

    from countersign.approved_package.build import read_tar
    from countersign.approved_package.verify import verify_package

    from ..standalone_tool import standalone_verifier

    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": _clean_team()},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    number = new_version(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = prepare(supervisor, submit(world, number), signer)
    signed = prepared["statement"]["predicate"]["exports"]
    members = {m["vehicle"]: m["orders"]["id"] for m in _clean_team()["team"]}
    assert sorted(signed) == sorted(f"vehicle/{member}.{orders_id}.{suffix}"
                                    for member, orders_id in members.items()
                                    for suffix in ("bhv", "imc", "moos"))
    submission = prepared["statement"]["predicate"]["submission"]
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": sign_prepared(prepared, signer),
                                     "password": PASSWORD})
    assert response.status_code == 201, response.text
    package = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{number}/package")
    assert package.status_code == 200, package.text
    files = read_tar(package.content)
    vehicle = {n: c for n, c in files.items() if n.startswith("vehicle/")}
    assert {n.split("/")[1].split(".")[0] for n in vehicle} == {"remus-100", "vehicle-2"}
    assert signed == {n: "sha256:" + hashlib.sha256(c).hexdigest() for n, c in vehicle.items()}
    # vehicle-2's mission file waits at meeting R1 for remus-100, and the reverse.
    moos = {n: c.decode() for n, c in vehicle.items() if n.endswith(".moos")}
    assert all("MEET_R1" in text for text in moos.values()), sorted(moos)
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    assert verify_package(package.content, log_key=log_key).ok
    assert standalone_verifier().verify(package.content, log_key)[1] == "OK"


def test_the_approvals_rehearsal_verdicts_read_each_member(world: World) -> None:
    """A team's rehearsal cited by its approval goes through the execution checker member by
    member, each against its own orders (the record holds each member's run fields)."""
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    assert operator.put(f"/api/missions/{MISSION}/draft", json={"orders": _clean_team()},
                        headers={"If-Match": mission.headers["ETag"]}).status_code == 200
    number = new_version(world)
    started = operator.post(f"/api/missions/{MISSION}/rehearsals",
                            json={"source": "simulate", "speed": 100_000, "version": number})
    assert started.status_code == 201, started.text
    rid = started.json()["id"]
    deadline = time.monotonic() + 300  # bounds a hang on a shared machine; times nothing
    while operator.get(f"/api/rehearsals/{rid}").json()["status"]["state"] != "finished":
        assert time.monotonic() < deadline
        time.sleep(0.1)
    digest = operator.post(f"/api/rehearsals/{rid}/stop").json()["digest"]
    submitted = operator.post(f"/api/missions/{MISSION}/versions/{number}/submit",
                              json={"rehearsal": digest})
    assert submitted.status_code == 201, submitted.text
    supervisor = world.client("supervisor")
    approval = approve(world, supervisor, register_key(supervisor), submitted.json()["id"])
    answer = world.client("auditor").get(f"/api/approvals/{approval['id']}/executions")
    assert answer.status_code == 200, answer.text
    runs = answer.json()["rehearsal"]
    assert [r["vehicle"] for r in runs] == ["remus-100", "vehicle-2"]
    for run in runs:
        assert run["verdict"]["terminal"] == "COMPLETE", run
        assert run["verdict"]["deviations"] == [], run
