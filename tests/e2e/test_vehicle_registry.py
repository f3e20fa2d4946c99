"""In the browser: an admin creates and edits a vehicle in the registry
(`/vehicles`), each changed save is a new version with a diff; an operator picks the vehicle
from the registry in the mission editor and gets its trusted behaviours as suggestions; an
approval whose vehicle profile the registry has since changed shows "needs re-approval" with
the profile diff."""

from __future__ import annotations

import contextlib
import json
import re
from collections.abc import Iterator
from typing import Any

import httpx
from playwright.sync_api import Page, expect

from countersign.approvals import dsse

from .conftest import PASSWORD, Server, _api_import, api_login
from .test_editor_build_exemplar import panel, saved
from .test_roles import sign_in


def exemplar() -> dict[str, Any]:
    from countersign.orders.examples import example_bytes

    data: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    return data


@contextlib.contextmanager
def client(server: Server, role: str) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=server.url, timeout=60) as session:
        login = api_login(session, role, PASSWORD[role])
        login.raise_for_status()
        session.headers["X-CSRF-Token"] = login.json()["csrf_token"]
        yield session


def test_admin_creates_edits_and_compares_vehicle_versions(page: Page) -> None:
    profile = {**exemplar()["vehicles"][0], "id": "e2e-registry-auv", "title": "Registry AUV"}
    sign_in(page, "admin")
    page.get_by_role("link", name="Vehicles", exact=True).click()
    expect(page.get_by_role("heading", name="Vehicle registry", level=1)).to_be_visible()
    page.get_by_role("button", name="New vehicle").click()
    page.get_by_label("Vehicle profile (JSON)").fill(json.dumps(profile, indent=2))
    page.get_by_role("button", name="Save vehicle").click()
    expect(page.get_by_role("status").filter(has_text="Vehicle e2e-registry-auv saved.")
           ).to_be_visible()
    expect(page.get_by_test_id("vehicle-versions").get_by_role("listitem")).to_have_count(1)

    page.get_by_role("button", name="Edit e2e-registry-auv").click()
    edited = {**profile, "behaviors": [*profile["behaviors"], "recover"]}
    page.get_by_label("Vehicle profile (JSON)").fill(json.dumps(edited, indent=2))
    page.get_by_role("button", name="Save vehicle").click()
    versions = page.get_by_test_id("vehicle-versions").get_by_role("listitem")
    expect(versions).to_have_count(2)
    expect(versions.first).to_contain_text("Version 2, saved by admin")
    before = ", ".join(profile["behaviors"])
    expect(page.get_by_test_id("vehicle-diff")).to_have_text(
        f"behaviors: {before} → {before}, recover")
    expect(page.get_by_role("row", name="e2e-registry-auv")).to_contain_text("recover")

    # A profile the server refuses is named, and no version is added.
    page.get_by_role("button", name="Edit e2e-registry-auv").click()
    page.get_by_label("Vehicle profile (JSON)").fill(json.dumps({**edited, "speed_mps": -1}))
    page.get_by_role("button", name="Save vehicle").click()
    expect(page.get_by_role("alert")).to_contain_text("speed_mps")


def test_operator_picks_the_vehicle_and_behaviours_from_the_registry(page: Page,
                                                                      server: Server) -> None:
    data = exemplar()
    profile = {**data.pop("vehicles")[0], "id": "e2e-picked-auv", "title": "Picked AUV"}
    profile["behaviors"] = [*profile["behaviors"], "e2e_hover"]
    data["id"] = "e2e-pick-vehicle"
    del data["vehicle"]
    with client(server, "admin") as admin:
        assert admin.put("/api/vehicles/e2e-picked-auv", json=profile).status_code == 200
    mission = _api_import(server, json.dumps(data).encode(), "application/json")

    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("node-G1")).to_be_visible()
    panel(page, "Mission")
    picker = page.get_by_role("combobox", name="Target vehicle")
    picker.click()
    picker.fill("Picked AUV")  # found by its title
    expect(page.get_by_role("option", name="e2e-picked-auv: Picked AUV · registry")
           ).to_have_count(1)
    page.get_by_role("option", name="e2e-picked-auv: Picked AUV · registry").click()
    saved(page)
    # The goal inspector's behaviour picker offers the registry vehicle's trusted behaviours.
    page.get_by_test_id("node-G1").click()
    page.get_by_role("combobox", name="Behaviour").click()
    expect(page.get_by_role("option", name=re.compile(r"^e2e_hover · trusted by e2e-picked-auv"))
           ).to_have_count(1)
    with client(server, "operator") as operator:
        draft = operator.get(f"/api/missions/{mission}").json()
    assert draft["orders"]["vehicle"] == "e2e-picked-auv"


def test_changed_profile_since_signing_needs_reapproval(page: Page, server: Server) -> None:
    data = exemplar()
    profile = {**data.pop("vehicles")[0], "id": "e2e-drift-auv"}
    data["id"], data["vehicle"] = "e2e-drift", "e2e-drift-auv"
    with client(server, "admin") as admin:
        assert admin.put("/api/vehicles/e2e-drift-auv", json=profile).status_code == 200
        mission = _api_import(server, json.dumps(data).encode(), "application/json")
        with client(server, "operator") as operator:
            number = operator.post(f"/api/missions/{mission}/versions").json()["number"]
            submitted = operator.post(f"/api/missions/{mission}/versions/{number}/submit")
            assert submitted.status_code == 201, submitted.text
        record = approve(server, submitted.json()["id"])
        slower = {**profile, "speed_mps": profile["speed_mps"] / 2}
        assert admin.put("/api/vehicles/e2e-drift-auv", json=slower).status_code == 200

    sign_in(page, "auditor")
    page.goto(f"/audit/{record}")
    drift = page.get_by_test_id("profile-drift")
    expect(drift).to_contain_text("Needs re-approval")
    expect(drift).to_contain_text("The signature stays valid for the profile it covered")
    expect(page.get_by_test_id("profile-drift-diff")).to_have_text(
        f"speed_mps: {json.dumps(profile['speed_mps'])} → {json.dumps(slower['speed_mps'])}")


def approve(server: Server, submission: int, decision: str = "approved", reason: str = "") -> int:
    """A supervisor signs the approval as a client does: a registered key, the server's PAE."""
    key = dsse.generate_key()
    with client(server, "supervisor") as supervisor:
        registered = supervisor.post("/api/keys", json={
            "public_key": dsse.public_text(key), "name": f"e2e {submission}",
            "password": PASSWORD["supervisor"]})
        assert registered.status_code == 201, registered.text
        key_id = registered.json()["key_id"]
        prepared = supervisor.post(f"/api/submissions/{submission}/statement",
                                   json={"decision": decision, "reason": reason,
                                         "key_id": key_id}).json()
        signature = key.sign(dsse.unb64(prepared["pae"], "pae"))
        envelope = json.dumps({"payloadType": prepared["payloadType"],
                               "payload": prepared["payload"],
                               "signatures": [{"keyid": key_id, "sig": dsse.b64(signature)}]})
        decided = supervisor.post(f"/api/submissions/{submission}/decision",
                                  json={"envelope": envelope,
                                        "password": PASSWORD["supervisor"]})
        assert decided.status_code == 201, decided.text
        record: int = decided.json()["id"]
        return record
