"""One throttle for every password check. Floods of wrong passwords
from one address, through sign-in and the decision route in parallel, leave the real user at
another address signing in on the first try, and no account has more than ten hashes checked
in any minute whatever the routes. Hashes are counted at the one hasher (store/hashing.py),
through which every route's check passes.

The floods last COUNTERSIGN_TEST_FLOOD_SECONDS (default 6; 60 s is the flood the throttle was
built against, which the limits, counted per minute, hold the same way)."""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from datetime import timedelta

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select

from countersign.store import login_throttle
from countersign.store.hashing import HASHER, HashingBusy
from countersign.store.tables import LoginAttempt

from .approval_helpers import new_version, prepare, register_key, sign_prepared, submit
from .conftest import PASSWORD, World

# Hashes are counted at the production hasher (tests/cheap_hashing.py swaps in a cheap one).
pytestmark = pytest.mark.production_hashing
FLOOD_SECONDS = float(os.environ.get("COUNTERSIGN_TEST_FLOOD_SECONDS", "6"))
ATTACKER, REAL_USER, OTHER = "203.0.113.66", "198.51.100.7", "192.0.2.12"


@dataclass
class Hashes:
    """The password hashes checked, with the monotonic time of each."""

    times: list[float] = field(default_factory=list)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def most_in_a_minute(self) -> int:
        times = sorted(self.times)
        return max((sum(1 for t in times[i:] if t - start < 60)
                    for i, start in enumerate(times)), default=0)


@pytest.fixture
def hashes(monkeypatch: pytest.MonkeyPatch) -> Iterator[Hashes]:
    seen = Hashes()
    original = HASHER.verify

    def counting(stored: str | bytes, password: str | bytes) -> bool:
        # Counted when a hash was checked, right or wrong, at the time it was asked for; a
        # full queue (HashingBusy, a 503) checks none, and the throttle forgets that attempt.
        began = time.monotonic()
        try:
            return original(stored, password)
        except HashingBusy:
            began = math.nan
            raise
        finally:
            if not math.isnan(began):
                with seen.lock:
                    seen.times.append(began)

    monkeypatch.setattr(HASHER, "verify", counting)
    yield seen


def _client(world: World, address: str, role: str | None = None) -> TestClient:
    client = TestClient(world.app, raise_server_exceptions=False, client=(address, 50000))
    if role is not None:
        client.headers["Authorization"] = f"Bearer {world.tokens[role]}"
    return client


def _flood(attacks: list[Callable[[], int]], seconds: float = FLOOD_SECONDS,
           parallel: int = 40) -> list[int]:
    """`parallel` threads, each repeating its attack (round robin) until the time is up."""
    statuses: list[int] = []
    lock = threading.Lock()
    deadline = time.monotonic() + seconds

    def run(n: int) -> None:
        while time.monotonic() < deadline:
            status = attacks[n % len(attacks)]()
            with lock:
                statuses.append(status)

    threads = [threading.Thread(target=run, args=(n,)) for n in range(parallel)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return statuses


def _decision_attack(world: World, address: str) -> Callable[[], int]:
    """A wrong password on a validly signed decision of the real supervisor's key."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    attacker = _client(world, address, "supervisor")

    def attack() -> int:
        return attacker.post(f"/api/submissions/{submission}/decision",
                             json={"envelope": envelope, "password": "guess 1234"}).status_code
    return attack


def _sign_in_attack(world: World, address: str, username: str) -> Callable[[], int]:
    attacker = _client(world, address)

    def attack() -> int:
        return attacker.post("/api/auth/login", json={"username": username,
                                                      "password": "guess 1234"}).status_code
    return attack


def test_floods_from_one_address_leave_the_real_user_signing_in(world: World,
                                                                 hashes: Hashes) -> None:
    name = world.usernames["supervisor"]
    attacks = [_sign_in_attack(world, ATTACKER, name), _decision_attack(world, ATTACKER)]
    hashes.times.clear()  # register_key checked the real password once
    statuses = _flood(attacks)
    assert set(statuses) <= {401, 403, 429, 503}, sorted(set(statuses))
    assert 429 in statuses
    real = _client(world, REAL_USER).post("/api/auth/login",
                                          json={"username": name, "password": PASSWORD})
    assert real.status_code == 200, real.text
    print(f"flood {FLOOD_SECONDS:.0f} s, {len(statuses)} requests: {len(hashes.times)} hashes, "
          f"at most {hashes.most_in_a_minute()} in a minute; real user: {real.status_code}")
    # The attacker's address gets half the account's minute; the real user's try is one more.
    assert hashes.most_in_a_minute() <= login_throttle.ADDRESS_HASHES_PER_MINUTE + 1


def test_at_most_ten_hashes_per_account_per_minute_whatever_the_route(
        world: World, hashes: Hashes) -> None:
    name = world.usernames["supervisor"]
    decision = _decision_attack(world, ATTACKER)
    hashes.times.clear()

    def on(address: str) -> list[Callable[[], int]]:
        client = _client(world, address, "supervisor")
        return [
            _sign_in_attack(world, address, name),
            lambda: client.post("/api/keys", json={"public_key": "x", "name": "k",
                                                   "password": "guess 1234"}).status_code,
            lambda: client.post("/api/tokens", json={"name": "t", "scopes": ["decide"],
                                                     "password": "guess 1234"}).status_code,
            lambda: client.post("/api/auth/password", json={
                "current_password": "guess 1234",
                "new_password": "violet tugboat marmalade 42"}).status_code,
        ]
    attacks = [decision, *on(ATTACKER), *on(REAL_USER), *on(OTHER)]
    statuses = _flood(attacks, parallel=30)
    assert set(statuses) <= {400, 401, 403, 422, 429, 503}, sorted(set(statuses))
    assert hashes.most_in_a_minute() <= login_throttle.ACCOUNT_HASHES_PER_MINUTE


def _age_attempts(world: World, seconds: float) -> None:
    with world.database.session() as db:
        for row in db.scalars(select(LoginAttempt)):
            row.at -= timedelta(seconds=seconds)


def test_one_address_gets_half_the_accounts_minute(world: World, hashes: Hashes,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    # Waiting out each back-off (1, 2, 4, 8, 16 s: 31 s) would give one address ten hashes in
    # a minute, the whole account's, and the real user elsewhere a 429. The throttle's clock
    # moves by the waits alone: on a loaded machine the ten hashes themselves took 30 s, and
    # the first attempt then left the minute before the last.
    clock = [login_throttle.utcnow()]
    monkeypatch.setattr(login_throttle, "utcnow", lambda: clock[0])
    attack = _sign_in_attack(world, ATTACKER, world.usernames["admin"])
    for wait in (0, 0, 0, 0, 0, 1, 2, 4, 8, 16):
        clock[0] += timedelta(seconds=wait + 0.1)
        assert attack() in (401, 429)
    assert len(hashes.times) == login_throttle.ADDRESS_HASHES_PER_MINUTE
    assert _client(world, REAL_USER).post("/api/auth/login", json={
        "username": world.usernames["admin"], "password": PASSWORD}).status_code == 200


def test_refusals_of_the_address_limit_are_not_account_failures(world: World) -> None:
    # An address past its limit is refused without a hash, and the refusal is forgotten: the
    # account's back-off (and the real user elsewhere) never sees it.
    with world.database.session() as db:
        db.add_all(LoginAttempt(username=f"sprayed{n}", address=ATTACKER, outcome="failed")
                   for n in range(login_throttle.ADDRESS_MAX_FAILURES))
    attack = _sign_in_attack(world, ATTACKER, world.usernames["admin"])
    assert [attack() for _ in range(60)] == [429] * 60
    with world.database.session() as db:
        assert not db.scalars(select(LoginAttempt).where(
            LoginAttempt.username == world.usernames["admin"])).all()
    assert _client(world, REAL_USER).post("/api/auth/login", json={
        "username": world.usernames["admin"], "password": PASSWORD}).status_code == 200


def test_every_route_counts_the_clients_address(world: World) -> None:
    # The decision route used to record no address: its failures then counted against every
    # address, the real user's too.
    decision = _decision_attack(world, ATTACKER)
    assert decision() == 403
    spoofed = _client(world, ATTACKER, "supervisor")
    spoofed.headers["X-Forwarded-For"] = REAL_USER  # not a trusted proxy: ignored
    assert spoofed.post("/api/keys", json={"public_key": "x", "name": "k",
                                           "password": "guess 1234"}).status_code == 403
    with world.database.session() as db:
        failed = db.scalars(select(LoginAttempt.address)
                            .where(LoginAttempt.outcome == "failed")).all()
    assert failed == [ATTACKER, ATTACKER]


@pytest.mark.parametrize(("address", "counted"), [
    ("2001:db8:1:2:3:4:5:6", "2001:db8:1:2::/64"),
    ("2001:db8:1:2:ffff::1", "2001:db8:1:2::/64"),
    ("::ffff:203.0.113.9", "203.0.113.9"),
    ("203.0.113.9", "203.0.113.9"),
    ("testclient", "testclient"),
    (None, None),
])
def test_ipv6_clients_are_counted_by_their_64(address: str | None, counted: str | None) -> None:
    assert login_throttle.counted_address(address) == counted
