"""Whatever can make someone able to decide needs the acting user's password, entered again: an
admin's session or `write` token alone cannot reset a supervisor's password, create a supervisor
or admin, and a session alone cannot mint a token with the `decide` scope. Refusals write
nothing and log nothing."""

from __future__ import annotations

from fastapi.testclient import TestClient
from httpx import Response

from .conftest import PASSWORD, World, count_rows

NEW = "a brand new long password 9"
WRONG = "not my password at all"
WRITES = ("SELECT count(*) FROM events", "SELECT count(*) FROM users",
          "SELECT count(*) FROM api_tokens", "SELECT count(*) FROM sessions")


def _written(world: World) -> tuple[int, ...]:
    return tuple(count_rows(world.database, sql) for sql in WRITES)


def _admins(world: World) -> dict[str, TestClient]:
    """The admin's cookie session and a `write`-only API token minted from it."""
    browser, csrf = world.browser("admin")
    browser.headers["X-CSRF-Token"] = csrf
    made = browser.post("/api/tokens", json={"name": "w", "scopes": ["read", "write"]})
    assert made.status_code == 201, made.text
    token = world.client()
    token.headers["Authorization"] = f"Bearer {made.json()['token']}"
    return {"session": browser, "write token": token}


def _refused(response: Response, words: str) -> None:
    assert response.status_code == 403, response.text
    detail = response.json()["detail"]
    assert words in detail, detail


def _signs_in(world: World, username: str, password: str) -> bool:
    response = world.client().post("/api/auth/login",
                                   json={"username": username, "password": password})
    return response.status_code == 200


def test_resetting_a_supervisors_password_needs_the_admins(world: World) -> None:
    clients = _admins(world)
    supervisor = next(u for u in clients["session"].get("/api/users").json()
                      if u["role"] == "supervisor")
    url = f"/api/users/{supervisor['id']}"
    for via, admin in clients.items():
        before = _written(world)
        _refused(admin.patch(url, json={"password": NEW}), "admin_password")
        _refused(admin.patch(url, json={"password": NEW, "admin_password": WRONG}),
                 "no password was reset")
        assert _written(world) == before, via
        assert _signs_in(world, supervisor["username"], PASSWORD), via
    # With the admin's password the reset is made (by the session; the token likewise).
    for via, admin in clients.items():
        password = f"{NEW} {via}"
        done = admin.patch(url, json={"password": password, "admin_password": PASSWORD})
        assert done.status_code == 200, (via, done.text)
        assert _signs_in(world, supervisor["username"], password), via


def test_creating_a_supervisor_or_an_admin_needs_the_admins_password(world: World) -> None:
    clients = _admins(world)
    for via, admin in clients.items():
        for role in ("supervisor", "admin"):
            name = f"new-{role}-{via.replace(' ', '-')}"
            body = {"username": name, "role": role, "password": NEW}
            before = _written(world)
            _refused(admin.post("/api/users", json=body), "admin_password")
            _refused(admin.post("/api/users", json={**body, "admin_password": WRONG}),
                     "no user was created")
            assert _written(world) == before, (via, role)
            assert not _signs_in(world, name, NEW)
            made = admin.post("/api/users", json={**body, "admin_password": PASSWORD})
            assert made.status_code == 201, (via, role, made.text)
            assert _signs_in(world, name, NEW)
    # An operator or auditor cannot decide or grant: no password asked.
    for role in ("operator", "auditor"):
        made = clients["session"].post("/api/users", json={
            "username": f"plain-{role}", "role": role, "password": NEW})
        assert made.status_code == 201, made.text


def test_a_token_that_can_decide_needs_your_password(world: World) -> None:
    browser, csrf = world.browser("supervisor")
    browser.headers["X-CSRF-Token"] = csrf
    before = _written(world)
    for body in ({"name": "d", "scopes": ["decide"]},
                 {"name": "d", "scopes": ["read", "write", "decide"], "password": ""}):
        _refused(browser.post("/api/tokens", json=body), "(password)")
    _refused(browser.post("/api/tokens", json={"name": "d", "scopes": ["read", "decide"],
                                               "password": WRONG}), "no token was created")
    assert _written(world)[0] == before[0] and _written(world)[2] == before[2]
    made = browser.post("/api/tokens", json={"name": "d", "scopes": ["read", "decide"],
                                             "password": PASSWORD})
    assert made.status_code == 201 and made.json()["scopes"] == ["read", "decide"], made.text
    # Without `decide` no password is asked, and the default scopes leave it out.
    plain = browser.post("/api/tokens", json={"name": "plain"})
    assert plain.status_code == 201 and plain.json()["scopes"] == ["read", "write"], plain.text


def test_wrong_passwords_for_a_grant_are_throttled_like_sign_in(world: World) -> None:
    admin = _admins(world)["session"]
    body = {"username": "hammer", "role": "supervisor", "password": NEW,
            "admin_password": WRONG}
    statuses = [admin.post("/api/users", json=body).status_code for _ in range(12)]
    assert 429 in statuses, statuses
    assert not _signs_in(world, "hammer", NEW)
