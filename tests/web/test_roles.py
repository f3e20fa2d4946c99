"""Every route declares its roles (x-roles in the OpenAPI document) and the server enforces
exactly them: 401 anonymous, 403 for a role not listed, anything else for a listed role."""

from __future__ import annotations

import re

import pytest

from .conftest import ROLES, World
from .roles_reviewed import REVIEWED_ROLES

PATH_VALUES = {"mission_id": "search-and-sample", "number": "1", "user_id": "999",
               "token_id": "999", "vehicle_id": "remus-100", "submission_id": "999",
               "approval_id": "999", "key_id": "0" * 64,
               "rehearsal_id": "no-such-rehearsal", "digest": "sha256:" + "0" * 64,
               "campaign_id": "0" * 16,
               "name": "search-and-sample", "format": "imc",
               "chart_id": "no-such-chart", "version": "1"}


def _routes(world: World) -> list[tuple[str, str, list[str]]]:
    routes = []
    for path, operations in world.app.openapi()["paths"].items():
        for method, operation in operations.items():
            roles = operation.get("x-roles")
            assert roles, f"{method.upper()} {path} declares no roles"
            routes.append((method.upper(), path, roles))
    return routes


def _call(world: World, role: str | None, method: str, path: str) -> int:
    concrete = re.sub(r"\{(\w+)\}", lambda m: PATH_VALUES[m.group(1)], path)
    # DELETE of the shared mission would change what later calls see; use a missing one.
    if method == "DELETE" and "missions" in path:
        concrete = concrete.replace("search-and-sample", "no-such-mission")
    client = world.client(role)
    body = None if method in ("GET", "DELETE") else {}
    return client.request(method, concrete, json=body).status_code


def test_route_roles_equal_the_reviewed_table(world: World) -> None:
    """Opening deleteMission or listLogEntries to every role must fail a test. The
    enforced roles (x-roles is what RoleGuard enforces, checked by the test below) must equal
    the committed, reviewed table; a new or changed route needs an entry there."""
    declared = {operation["operationId"]: tuple(operation.get("x-roles") or ())
                for operations in world.app.openapi()["paths"].values()
                for operation in operations.values()}
    missing = sorted(set(declared) - set(REVIEWED_ROLES))
    assert not missing, f"add these operations to tests/web/roles_reviewed.py: {missing}"
    gone = sorted(set(REVIEWED_ROLES) - set(declared))
    assert not gone, f"these reviewed operations no longer exist: {gone}"
    changed = {op: (declared[op], REVIEWED_ROLES[op]) for op in declared
               if set(declared[op]) != set(REVIEWED_ROLES[op])}
    assert not changed, f"roles differ from the reviewed table (route, reviewed): {changed}"


def test_every_route_declares_roles_and_they_hold(world: World) -> None:
    routes = _routes(world)
    assert len(routes) >= 20
    for method, path, roles in routes:
        anonymous = _call(world, None, method, path)
        if "anonymous" in roles:
            assert anonymous not in (401, 403), (method, path)
        else:
            assert anonymous == 401, (method, path, anonymous)
        for role in ROLES:
            status = _call(world, role, method, path)
            if path == "/api/tokens" and method == "POST":
                assert status == 403  # tokens never mint tokens (test_account_hygiene.py)
            elif role in roles or "anonymous" in roles:
                assert status not in (401, 403), (role, method, path, status)
                assert status < 500, (role, method, path, status)
            else:
                assert status == 403, (role, method, path, status)


@pytest.mark.parametrize("role", ["supervisor", "auditor", "admin"])
def test_only_operators_write_missions(world: World, role: str) -> None:
    client = world.client(role)
    assert client.post("/api/missions", json={"id": "x"}).status_code == 403
    assert client.get("/api/missions").status_code == 200


def test_operators_cannot_read_the_event_log_or_users(world: World) -> None:
    client = world.client("operator")
    assert client.get("/api/events").status_code == 403
    assert client.get("/api/users").status_code == 403
    assert world.client("auditor").get("/api/events").status_code == 200
