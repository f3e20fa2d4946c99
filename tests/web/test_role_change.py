"""A role change needs the admin's password, entered again; the event names
whose role changed, from what to what."""

from __future__ import annotations

from .conftest import PASSWORD, World


def test_role_change_needs_the_admins_password(world: World) -> None:
    admin = world.client("admin")
    made = admin.post("/api/users", json={"username": "frank", "role": "operator",
                                          "password": "another long password 7"})
    assert made.status_code == 201, made.text
    url = f"/api/users/{made.json()['id']}"
    missing = admin.patch(url, json={"role": "admin"})
    assert missing.status_code == 403 and "password" in missing.json()["detail"]
    wrong = admin.patch(url, json={"role": "admin", "admin_password": "not my password"})
    assert wrong.status_code == 403
    users = {u["username"]: u["role"] for u in admin.get("/api/users").json()}
    assert users["frank"] == "operator"
    changed = admin.patch(url, json={"role": "auditor", "admin_password": PASSWORD})
    assert changed.status_code == 200, changed.text and changed.json()["role"] == "auditor"
    # Other changes (a display name) need no password.
    assert admin.patch(url, json={"display_name": "Frank"}).status_code == 200
    events = admin.get("/api/events", params={"limit": 1000}).json()
    role_events = [e for e in events if e["kind"] == "user.updated" and "role" in e["detail"]]
    assert role_events[-1]["detail"] == {"user": "frank", "previous_role": "operator",
                                         "role": "auditor"}
