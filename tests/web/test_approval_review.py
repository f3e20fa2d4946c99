"""The review route behind the browser's review page: a version's orders, plain orders,
findings, paths, submissions, the previously approved version (for the diff), and whether the
caller may submit it or sign a decision on it, with the reason when not."""

from __future__ import annotations

from typing import Any

from countersign.store.accounts import create_token

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import PASSWORD, World


def _review(world: World, role: str, number: int) -> dict[str, Any]:
    response = world.client(role).get(f"/api/missions/{MISSION}/versions/{number}/review")
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def test_review_shows_the_version_and_who_may_act(world: World) -> None:
    number = new_version(world)
    review = _review(world, "operator", number)
    assert review["digest"].startswith("sha256:") and review["orders"]["id"] == MISSION
    assert "Search Area A" in review["plain"] and review["ok"] is True
    assert review["paths"]["count"] == 75 and "path_items" not in review
    # The review page lists the version's paths from the paths route, a page at a time.
    page = world.client("operator").get(f"/api/missions/{MISSION}/paths",
                                        params={"version": number, "limit": 50}).json()
    assert page["count"] == 75 and len(page["items"]) == 50 and page["items"][0]["index"] == 1
    assert review["submissions"] == [] and review["previous"] is None
    assert review["may_submit"] is True and review["submit_refusal"] is None
    assert review["may_decide"] is False
    assert "may not sign decisions" in review["decide_refusal"]

    supervisor = _review(world, "supervisor", number)
    assert supervisor["may_submit"] is False
    assert supervisor["submit_refusal"] == "only operators submit versions"
    assert supervisor["decide_refusal"] == "the version is not submitted"

    submission = submit(world, number)
    review = _review(world, "operator", number)
    assert review["submissions"][0]["id"] == submission
    assert review["submissions"][0]["state"] == "submitted"
    assert review["submit_refusal"] == f"version {number} is submitted already"
    assert _review(world, "supervisor", number)["may_decide"] is True


def test_review_names_the_previously_approved_version(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    first = new_version(world)
    approval = approve(world, supervisor, signer, submit(world, first))
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    orders["goals"][0]["title"] = "Search Area A, north half"
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    second = new_version(world)
    review = _review(world, "auditor", second)
    previous = review["previous"]
    assert previous["version"] == first and previous["approval"] == approval["id"]
    assert previous["state"] == "approved"
    assert previous["orders"]["goals"][0]["title"] != review["orders"]["goals"][0]["title"]
    assert _review(world, "auditor", first)["previous"] is None
    decided = _review(world, "supervisor", first)
    assert decided["may_decide"] is False and "is approved" in decided["decide_refusal"]


def test_review_tells_a_supervisor_who_authored_the_version_why_not(world: World) -> None:
    admin = world.client("admin")
    created = admin.post("/api/users", json={"username": "dual", "role": "operator",
                                             "password": PASSWORD})
    assert created.status_code == 201, created.text
    with world.database.session() as db:
        from countersign.store.tables import User

        user = db.get_one(User, created.json()["id"])
        token = create_token(db, user=user, name="tests", signer=world.database.log_signer)[1]
    dual = world.client()
    dual.headers["Authorization"] = f"Bearer {token}"
    number = dual.post(f"/api/missions/{MISSION}/versions").json()["number"]
    submit(world, number)
    assert admin.patch(f"/api/users/{created.json()['id']}",
                       json={"role": "supervisor", "admin_password": PASSWORD}).status_code == 200
    review = dual.get(f"/api/missions/{MISSION}/versions/{number}/review").json()
    assert review["may_decide"] is False
    assert review["decide_refusal"].startswith("separation of duties")


def test_review_of_a_missing_version_is_404(world: World) -> None:
    response = world.client("auditor").get(f"/api/missions/{MISSION}/versions/99/review")
    assert response.status_code == 404
    assert "no version 99" in response.json()["detail"]
