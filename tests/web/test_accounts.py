from __future__ import annotations

import pytest
from sqlalchemy import select

from countersign.store.accounts import MAX_LISTED_TOKENS, MAX_LIVE_TOKENS
from countersign.store.hashing import HASHER
from countersign.store.login_throttle import FREE_FAILURES
from countersign.store.tables import ApiToken, User

from .conftest import PASSWORD, World, count_rows
from .write_lock import probe_write_lock


def test_login_sets_a_hardened_cookie_and_returns_csrf(world: World) -> None:
    client = world.client()
    response = client.post("/api/auth/login",
                           json={"username": "operator1", "password": PASSWORD})
    assert response.status_code == 200
    cookie = response.headers["set-cookie"].lower()
    assert "httponly" in cookie and "samesite=strict" in cookie
    body = response.json()
    assert body["user"]["role"] == "operator" and len(body["csrf_token"]) > 20
    assert client.get("/api/auth/me").json()["user"]["username"] == "operator1"


@pytest.mark.production_hashing  # the stored hashes are production's
def test_passwords_are_stored_as_argon2_hashes(world: World) -> None:
    with world.database.engine.connect() as connection:
        from sqlalchemy import text

        hashes = connection.execute(text("SELECT password_hash FROM users")).scalars().all()
    assert hashes and all(h.startswith("$argon2id$") for h in hashes)
    assert all(PASSWORD not in h for h in hashes)


def test_state_changes_with_a_cookie_need_the_csrf_header(world: World) -> None:
    client, csrf = world.browser("operator")
    orders = client.get("/api/missions/search-and-sample").json()["orders"]
    orders["id"] = "copy-1"
    refused = client.post("/api/missions", json=orders)
    assert refused.status_code == 403 and "X-CSRF-Token" in refused.json()["detail"]
    wrong = client.post("/api/missions", json=orders, headers={"X-CSRF-Token": "nope"})
    assert wrong.status_code == 403
    accepted = client.post("/api/missions", json=orders, headers={"X-CSRF-Token": csrf})
    assert accepted.status_code == 201


def test_wrong_password_is_a_problem_document_and_rate_limited(world: World) -> None:
    client = world.client()
    for attempt in range(FREE_FAILURES + 5):  # then a 32 s wait: longer than this test takes
        response = client.post("/api/auth/login", json={"username": "admin1", "password": "x"})
        if response.status_code == 429 and attempt >= FREE_FAILURES:
            continue  # the back-off already applies
        assert response.status_code == 401
        assert response.headers["content-type"].startswith("application/problem+json")
        assert response.json()["detail"] == "wrong username or password"
    blocked = client.post("/api/auth/login", json={"username": "admin1", "password": PASSWORD})
    assert blocked.status_code == 429
    # Another account is not affected.
    ok = client.post("/api/auth/login", json={"username": "auditor1", "password": PASSWORD})
    assert ok.status_code == 200


def test_logout_ends_the_session(world: World) -> None:
    client, csrf = world.browser("auditor")
    assert client.post("/api/auth/logout", headers={"X-CSRF-Token": csrf}).status_code == 204
    assert client.get("/api/auth/me").status_code == 401


def test_api_tokens_are_shown_once_and_can_be_revoked(world: World) -> None:
    client, csrf = world.browser("supervisor")
    client.headers["X-CSRF-Token"] = csrf
    created = client.post("/api/tokens", json={"name": "ci"}).json()
    assert created["token"].startswith("cst_")
    listed = client.get("/api/tokens").json()
    assert all(t.get("token") is None for t in listed)
    bearer = world.client()
    bearer.headers["Authorization"] = f"Bearer {created['token']}"
    assert bearer.get("/api/missions").status_code == 200
    assert client.delete(f"/api/tokens/{created['id']}").status_code == 204
    assert bearer.get("/api/missions").status_code == 401


def test_admin_manages_users_and_every_change_is_logged(world: World) -> None:
    admin = world.client("admin")
    made = admin.post("/api/users", json={"username": "carol", "role": "supervisor",
                                          "password": "another long password",
                                          "admin_password": PASSWORD})
    assert made.status_code == 201
    weak = admin.post("/api/users", json={"username": "dave", "role": "operator",
                                          "password": "short"})
    assert weak.status_code == 400 and "at least" in weak.json()["detail"]
    disabled = admin.patch(f"/api/users/{made.json()['id']}", json={"disabled": True})
    assert disabled.json()["disabled"] is True
    assert count_rows(world.database,
                      "SELECT count(*) FROM events WHERE kind LIKE 'user.%'") >= 6


@pytest.mark.production_hashing  # patches the one hasher sign-in uses
def test_passwords_are_checked_without_holding_the_write_lock(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """argon2 takes tens of milliseconds by design: on SQLite, checking a password while
    holding the one write lock would make every other writer wait for each sign-in."""
    writable_meanwhile = probe_write_lock(world, monkeypatch, HASHER, "verify")
    client = world.client()
    assert client.post("/api/auth/login",
                       json={"username": "operator1", "password": PASSWORD}).status_code == 200
    assert client.post("/api/auth/login",
                       json={"username": "operator1", "password": "wrong"}).status_code == 401
    assert writable_meanwhile == [True, True]


@pytest.mark.production_hashing  # patches the one hasher account creation uses
def test_a_new_users_password_is_hashed_without_holding_the_write_lock(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """Creating an account hashes its password (argon2, tens of milliseconds by design) before
    the write transaction begins, not while other writers wait for SQLite's one lock."""
    writable_meanwhile = probe_write_lock(world, monkeypatch, HASHER, "hash")
    made = world.client("admin").post("/api/users", json={
        "username": "erin", "role": "operator", "password": "a long enough passphrase 7"})
    assert made.status_code == 201, made.text
    assert writable_meanwhile == [True]


def test_look_alike_usernames_are_refused(world: World) -> None:
    # Another account that reads as an existing one ('ADMIN', fullwidth or Cyrillic letters)
    # would pass as that person in the log and on approvals.
    admin = world.client("admin")
    existing = world.usernames["admin"]
    for look_alike, words in ((existing.upper(), "is taken"),
                              ("\uff41" + existing[1:], "ASCII letters"),
                              ("\u0430" + existing[1:], "ASCII letters")):
        refused = admin.post("/api/users", json={"username": look_alike, "role": "admin",
                                                 "password": "another long password",
                                                 "admin_password": PASSWORD})
        assert refused.status_code == 400, (look_alike, refused.text)
        assert words in refused.json()["detail"]


def test_live_api_tokens_and_the_token_list_are_bounded(world: World) -> None:
    """Anyone signed in makes tokens: their number alive at once is bounded (409 naming the
    bound, room again after a revocation) and so is the list, live tokens first."""
    client, csrf = world.browser("auditor")
    client.headers["X-CSRF-Token"] = csrf
    live = len(client.get("/api/tokens").json())  # the world's own token
    made = [client.post("/api/tokens", json={"name": f"t{n}", "scopes": ["read"]})
            for n in range(MAX_LIVE_TOKENS - live)]
    assert all(r.status_code == 201 for r in made), [r.text for r in made if r.is_error][:1]
    refused = client.post("/api/tokens", json={"name": "one more", "scopes": ["read"]})
    assert refused.status_code == 409, refused.text
    assert f"at most {MAX_LIVE_TOKENS}" in refused.json()["detail"]
    assert client.delete(f"/api/tokens/{made[0].json()['id']}").status_code == 204
    again = client.post("/api/tokens", json={"name": "after a revocation", "scopes": ["read"]})
    assert again.status_code == 201, again.text
    with world.database.session() as db:
        user = db.scalars(select(User).where(User.username == world.usernames["auditor"])).one()
        db.add_all(ApiToken(user_id=user.id, name=f"old{n}", token_hash=f"{n:064x}",
                            scopes="read", revoked=True) for n in range(MAX_LISTED_TOKENS))
    listed = client.get("/api/tokens").json()
    assert len(listed) == MAX_LISTED_TOKENS
    assert sum(not t["revoked"] for t in listed) == MAX_LIVE_TOKENS
    assert [t["id"] for t in listed] == sorted(t["id"] for t in listed)
