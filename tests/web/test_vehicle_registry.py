"""Orders naming a vehicle without its profile get the registry's, copied into the
draft (and so into every version and approval digest); without one, VEHICLE."""

from __future__ import annotations

import json
from typing import Any

from countersign.orders.examples import example_bytes
from countersign.orders.model import Vehicle
from countersign.store.vehicles import vehicle_versions

from .conftest import World
from .described import assert_described


def orders_without_profile(mission_id: str) -> tuple[dict[str, Any], dict[str, Any]]:
    data: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    profile = data.pop("vehicles")[0]
    data["id"] = mission_id
    return data, profile


def codes(report: dict[str, Any]) -> list[str]:
    return [f["code"] for f in report["findings"]]


def test_no_profile_anywhere_is_vehicle(world: World) -> None:
    data, _ = orders_without_profile("no-profile")
    response = world.client("operator").post("/api/validate", json=data)
    assert response.status_code == 200, response.text
    assert "VEHICLE" in codes(response.json()) and not response.json()["ok"]


def test_registry_profile_is_copied_into_the_draft(world: World) -> None:
    data, profile = orders_without_profile("from-registry")
    admin = world.client("admin")
    assert admin.put(f"/api/vehicles/{profile['id']}", json=profile).status_code == 200
    operator = world.client("operator")
    response = operator.post("/api/validate", json=data)
    assert "VEHICLE" not in codes(response.json()), response.json()
    created = operator.post("/api/missions", json=data)
    assert created.status_code == 201, created.text
    mission = operator.get("/api/missions/from-registry").json()
    assert mission["orders"]["vehicles"][0]["id"] == profile["id"]
    assert mission["orders"]["vehicles"][0]["behaviors"] == profile["behaviors"]
    report = operator.get("/api/missions/from-registry/report").json()
    assert "VEHICLE" not in codes(report)


def test_each_changed_save_is_a_new_version(world: World) -> None:
    _, profile = orders_without_profile("versions")
    profile["id"] = "versioned-auv"
    admin = world.client("admin")
    assert admin.put("/api/vehicles/versioned-auv", json=profile).status_code == 200
    # Saving the same profile again adds no version.
    assert admin.put("/api/vehicles/versioned-auv", json=profile).status_code == 200
    changed = {**profile, "behaviors": [*profile["behaviors"], "recover"]}
    assert admin.put("/api/vehicles/versioned-auv", json=changed).status_code == 200
    versions = world.client("operator").get("/api/vehicles/versioned-auv/versions")
    assert versions.status_code == 200, versions.text
    listed = versions.json()
    assert [v["number"] for v in listed] == [2, 1]
    assert listed[0]["profile"]["behaviors"][-1] == "recover"
    assert "recover" not in listed[1]["profile"]["behaviors"]
    assert listed[0]["saved_by"]
    # The profiles answered are the stored ones, which the Vehicle model describes exactly.
    with world.database.session() as db:
        stored = [v.profile for v in vehicle_versions(db, "versioned-auv")]
    assert [v["profile"] for v in listed] == stored
    for each in stored:
        assert_described(Vehicle, each)
    missing = world.client("operator").get("/api/vehicles/no-such-auv/versions")
    assert missing.status_code == 404


def test_a_body_validated_again_after_a_registry_change_sees_the_change(world: World) -> None:
    # The body cache of /api/validate keys on the registry's state: the same bytes sent
    # before and after the profile is registered get different reports.
    data, profile = orders_without_profile("cached-body")
    profile["id"] = data["vehicle"] = "cache-probe-auv"
    body = json.dumps(data).encode()
    operator = world.client("operator")
    headers = {"Content-Type": "application/json"}
    before = operator.post("/api/validate", content=body, headers=headers)
    assert "VEHICLE" in codes(before.json()), before.json()
    admin = world.client("admin")
    assert admin.put(f"/api/vehicles/{profile['id']}", json=profile).status_code == 200
    after = operator.post("/api/validate", content=body, headers=headers)
    assert "VEHICLE" not in codes(after.json()), after.json()


def test_a_registry_change_brings_the_drafts_that_use_it_up_to_date(world: World) -> None:
    # a draft created before its vehicle was registered said VEHICLE until
    # someone edited it; a draft holding the registry's copy kept the old profile.
    data, profile = orders_without_profile("waits-for-profile")
    profile["id"] = data["vehicle"] = "late-auv"
    operator = world.client("operator")
    assert operator.post("/api/missions", json=data).status_code == 201
    edited, _ = orders_without_profile("own-copy")
    edited["vehicle"] = "late-auv"
    edited["vehicles"] = [{**profile, "title": "the operator's own copy"}]
    assert operator.post("/api/missions", json=edited).status_code == 201
    assert "VEHICLE" in codes(operator.get("/api/missions/waits-for-profile/report").json())
    revision = operator.get("/api/missions/waits-for-profile").json()["revision"]

    admin = world.client("admin")
    assert admin.put("/api/vehicles/late-auv", json=profile).status_code == 200
    waiting = operator.get("/api/missions/waits-for-profile").json()
    assert waiting["revision"] == revision + 1
    assert waiting["orders"]["vehicles"] == [profile]
    assert "VEHICLE" not in codes(operator.get("/api/missions/waits-for-profile/report").json())

    # The next registry change reaches the draft holding its copy, not the operator's own.
    slower = {**profile, "speed_mps": 1.0}
    assert admin.put("/api/vehicles/late-auv", json=slower).status_code == 200
    assert operator.get("/api/missions/waits-for-profile").json()["orders"]["vehicles"] == [
        slower]
    own = operator.get("/api/missions/own-copy").json()["orders"]["vehicles"]
    assert own[0]["title"] == "the operator's own copy" and own[0].get("speed_mps") != 1.0
