"""Sign-in throttling per account and address, counted before the hash; password
strength; token scopes, expiry and no minting by tokens; password change and reset revoke
sessions and tokens; idle and absolute session timeouts."""

from __future__ import annotations

import threading
from datetime import timedelta

import pytest
from sqlalchemy import select, update

from countersign.store import accounts, login_throttle
from countersign.store.hashing import HASHER
from countersign.store.tables import ApiToken, LoginAttempt, Session, utcnow

from .conftest import PASSWORD, World

NEW_PASSWORD = "violet tugboat marmalade 42"


def _age(world: World, table: type, seconds: float, **where: object) -> None:
    """Move rows' times into the past, as if that much time had passed."""
    column = {LoginAttempt: "at", Session: "created_at", ApiToken: "expires_at"}[table]
    with world.database.session() as db:
        query = select(table)
        for key, value in where.items():
            query = query.where(getattr(table, key) == value)
        for row in db.scalars(query):
            setattr(row, column, getattr(row, column) - timedelta(seconds=seconds))
            if table is Session:
                row.last_seen_at = None


def _login(world: World, username: str, password: str) -> int:
    return world.client().post("/api/auth/login",
                               json={"username": username, "password": password}).status_code


def test_an_attacked_account_is_slowed_not_locked_out(world: World) -> None:
    for _ in range(login_throttle.FREE_FAILURES + 5):
        assert _login(world, "admin1", "wrong password") in (401, 429)
    refused = world.client().post("/api/auth/login",
                                  json={"username": "admin1", "password": PASSWORD})
    assert refused.status_code == 429
    assert 1 <= int(refused.headers["Retry-After"]) <= 60
    # A minute later (the longest back-off), not 15, the real user signs in.
    _age(world, LoginAttempt, 61)
    assert _login(world, "admin1", PASSWORD) == 200


def test_waiting_as_told_lets_the_real_user_in(world: World) -> None:
    # A refused try must not restart or lengthen the wait: whoever waits Retry-After gets in,
    # and an attacker retrying every few seconds cannot keep the account shut.
    for _ in range(login_throttle.FREE_FAILURES):
        assert _login(world, "admin1", "wrong password") == 401
    for _ in range(3):
        refused = world.client().post("/api/auth/login",
                                      json={"username": "admin1", "password": "wrong again"})
        assert refused.status_code == 429
    _age(world, LoginAttempt, int(refused.headers["Retry-After"]) + 0.1)
    assert _login(world, "admin1", PASSWORD) == 200


def _try(world: World, username: str, password: str, address: str) -> str:
    """Sign-in's check from a given client address: 'ok', 'wrong' or 'throttled'."""
    with world.database.session() as db:
        try:
            user = accounts.authenticate(db, username=username, password=password,
                                         address=address)
        except accounts.TooManyAttempts:
            return "throttled"
        return "ok" if user is not None else "wrong"


def test_a_slow_attacker_elsewhere_does_not_keep_the_real_user_out(world: World) -> None:
    # One address guessing once a minute (the longest back-off) stays under the address limit
    # and has every try evaluated: its own next try is held back, the real user's is not.
    for _ in range(login_throttle.FREE_FAILURES + 3):
        assert _try(world, "admin1", "guess", "203.0.113.9") == "wrong"
        _age(world, LoginAttempt, 61)
    assert _try(world, "admin1", "guess", "203.0.113.9") == "wrong"
    assert _try(world, "admin1", "guess", "203.0.113.9") == "throttled"
    assert _try(world, "admin1", PASSWORD, "198.51.100.7") == "ok"


def test_many_addresses_together_meet_the_account_wide_back_off(world: World) -> None:
    for n in range(login_throttle.ACCOUNT_WIDE_FAILURES):
        if n and n % login_throttle.ACCOUNT_HASHES_PER_MINUTE == 0:
            _age(world, LoginAttempt, 61)  # a minute's hashes per account are limited too
        assert _try(world, "admin1", "guess", f"203.0.113.{n}") == "wrong"
    assert _try(world, "admin1", PASSWORD, "198.51.100.7") == "throttled"
    _age(world, LoginAttempt, 61)
    assert _try(world, "admin1", PASSWORD, "198.51.100.7") == "ok"


def test_spraying_many_accounts_from_one_address_is_limited(world: World) -> None:
    statuses = [_login(world, f"nobody{n}", "Winter2026!") for n in
                range(login_throttle.ADDRESS_MAX_FAILURES + 2)]
    assert statuses[0] == 401 and statuses[-1] == 429


@pytest.mark.production_hashing  # counts at the one hasher sign-in uses
def test_parallel_tries_are_counted_before_the_hash(world: World,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    evaluations = 0
    lock = threading.Lock()
    verify = HASHER.verify

    def counting(stored: str, password: str) -> bool:
        nonlocal evaluations
        with lock:
            evaluations += 1
        return verify(stored, password)

    # The one hasher every password check goes through (store/login_throttle.py).
    monkeypatch.setattr(HASHER, "verify", counting)
    statuses: list[int] = []

    def attack() -> None:
        status = _login(world, "operator1", "not the password")
        with lock:
            statuses.append(status)

    threads = [threading.Thread(target=attack) for _ in range(40)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert set(statuses) <= {401, 429} and 429 in statuses
    # At most one address's share of the account's minute, whatever the parallelism.
    assert evaluations <= login_throttle.ADDRESS_HASHES_PER_MINUTE, evaluations


@pytest.mark.parametrize("weak", ["aaaaaaaaaa", "password12", "qwertyuiop", "newuser1-x!",
                                  "1234567890"])
def test_weak_passwords_are_refused(world: World, weak: str) -> None:
    response = world.client("admin").post(
        "/api/users", json={"username": "newuser1", "role": "operator", "password": weak})
    assert response.status_code == 400, (weak, response.text)
    ok = world.client("admin").post(
        "/api/users", json={"username": "newuser1", "role": "operator", "password": NEW_PASSWORD})
    assert ok.status_code == 201


def test_tokens_cannot_mint_tokens(world: World) -> None:
    response = world.client("operator").post("/api/tokens", json={"name": "child"})
    assert response.status_code == 403
    assert "cannot create tokens" in response.json()["detail"]


def test_token_scopes_and_expiry(world: World) -> None:
    browser, csrf = world.browser("supervisor")
    browser.headers["X-CSRF-Token"] = csrf
    made = browser.post("/api/tokens", json={"name": "reader", "scopes": ["read"],
                                             "expires_in_days": 1}).json()
    assert made["scopes"] == ["read"] and made["expires_at"]
    reader = world.client()
    reader.headers["Authorization"] = f"Bearer {made['token']}"
    assert reader.get("/api/missions").status_code == 200
    refused = reader.post("/api/submissions/1/statement", json={})
    assert refused.status_code == 403 and "'decide' scope" in refused.json()["detail"]
    _age(world, ApiToken, 2 * 86400, id=made["id"])
    assert reader.get("/api/missions").status_code == 401
    bad = browser.post("/api/tokens", json={"name": "x", "scopes": ["admin"]})
    assert bad.status_code == 422


def test_password_change_revokes_sessions_and_tokens(world: World) -> None:
    other, _ = world.browser("operator")
    browser, csrf = world.browser("operator")
    token = world.client("operator")
    wrong = browser.post("/api/auth/password", headers={"X-CSRF-Token": csrf},
                         json={"current_password": "nope", "new_password": NEW_PASSWORD})
    assert wrong.status_code == 400
    weak = browser.post("/api/auth/password", headers={"X-CSRF-Token": csrf},
                        json={"current_password": PASSWORD, "new_password": "operator1-pass"})
    assert weak.status_code == 400
    changed = browser.post("/api/auth/password", headers={"X-CSRF-Token": csrf},
                           json={"current_password": PASSWORD, "new_password": NEW_PASSWORD})
    assert changed.status_code == 204, changed.text
    assert browser.get("/api/auth/me").status_code == 200  # the session that asked stays
    assert other.get("/api/auth/me").status_code == 401
    assert token.get("/api/missions").status_code == 401
    assert _login(world, "operator1", PASSWORD) == 401
    assert _login(world, "operator1", NEW_PASSWORD) == 200


def test_admin_reset_revokes_that_users_sessions_and_tokens(world: World) -> None:
    victim, _ = world.browser("auditor")
    token = world.client("auditor")
    admin = world.client("admin")
    users = {u["username"]: u["id"] for u in admin.get("/api/users").json()}
    reset = admin.patch(f"/api/users/{users['auditor1']}", json={"password": NEW_PASSWORD,
                                                                "admin_password": PASSWORD})
    assert reset.status_code == 200, reset.text
    assert victim.get("/api/auth/me").status_code == 401
    assert token.get("/api/approvals").status_code == 401
    assert admin.get("/api/users").status_code == 200


def test_sessions_time_out_when_idle_and_absolutely(world: World) -> None:
    idle, _ = world.browser("operator")
    assert idle.get("/api/auth/me").status_code == 200
    _age(world, Session, accounts.SESSION_IDLE.total_seconds() + 60)
    assert idle.get("/api/auth/me").status_code == 401
    old, _ = world.browser("operator")
    with world.database.session() as db:
        db.execute(update(Session).values(expires_at=utcnow() - timedelta(seconds=1),
                                          last_seen_at=utcnow()))
    assert old.get("/api/auth/me").status_code == 401
