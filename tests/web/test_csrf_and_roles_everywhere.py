"""Generated from the OpenAPI document: for every route, method and role, a cookie session's
change without the CSRF header (or with another session's) is refused with the CSRF error before
anything else, and a role the route's `x-roles` leaves out is refused with 403 even with the CSRF
header. The live rehearsal viewer (its page and its websocket, outside the OpenAPI document)
admits the roles that may watch a rehearsal (`getRehearsal`'s x-roles) and refuses the others."""

from __future__ import annotations

import re

import pytest
from fastapi.testclient import TestClient
from starlette.testclient import WebSocketDenialResponse

from countersign.web.deps import CSRF_HEADER

from .conftest import ROLES, World
from .test_roles import PATH_VALUES

CHANGES = ("POST", "PUT", "PATCH", "DELETE")
# Routes that need no sign-in take no session, so no CSRF header either.
NO_SESSION = {"login", "health"}
CSRF_REFUSAL = f"missing or wrong {CSRF_HEADER} header"


def _operations(world: World) -> list[tuple[str, str, str, list[str]]]:
    found = []
    for path, operations in world.app.openapi()["paths"].items():
        for method, operation in operations.items():
            concrete = re.sub(r"\{(\w+)\}", lambda m: PATH_VALUES[m.group(1)], path)
            found.append((method.upper(), concrete, operation["operationId"],
                          operation["x-roles"]))
    return found


def _send(client: TestClient, method: str, path: str, csrf: str | None) -> tuple[int, str]:
    headers = {CSRF_HEADER: csrf} if csrf is not None else {}
    body = None if method in ("GET", "HEAD", "DELETE") else {}
    response = client.request(method, path, json=body, headers=headers)
    try:
        detail = str(response.json().get("detail", ""))
    except (ValueError, AttributeError):
        detail = response.text[:200]
    return response.status_code, detail


def test_every_change_needs_the_csrf_header_and_every_route_its_roles(world: World) -> None:
    sessions = {role: world.browser(role) for role in ROLES}
    operations = _operations(world)
    methods = {method for method, *_ in operations}
    assert {"POST", "PUT", "PATCH", "DELETE"} <= methods, methods
    anonymous = {op for _, _, op, roles in operations if "anonymous" in roles}
    assert anonymous == NO_SESSION, "a new route without sign-in: review its CSRF exposure"
    checked = 0
    for method, path, operation, allowed in operations:
        if operation in NO_SESSION:
            continue
        for role, (client, csrf) in sessions.items():
            other_csrf = sessions["auditor" if role != "auditor" else "admin"][1]
            if method in CHANGES:
                for sent in (None, other_csrf):
                    status, detail = _send(client, method, path, sent)
                    assert (status, detail) == (403, CSRF_REFUSAL), (
                        role, method, path, sent is not None, status, detail)
                    checked += 1
            if role not in allowed:
                status, detail = _send(client, method, path, csrf)
                assert status == 403 and f"the {role} role may not" in detail, (
                    role, method, path, status, detail)
                checked += 1
    # Each refused request left every session signed in (nothing ran, not even a logout).
    for role, (client, _) in sessions.items():
        assert client.get("/api/auth/me").status_code == 200, role
    assert checked > 300, checked


def test_only_the_roles_that_may_watch_open_a_live_rehearsal(world: World) -> None:
    watchers = next(operation["x-roles"] for operations in world.app.openapi()["paths"].values()
                    for operation in operations.values()
                    if operation["operationId"] == "getRehearsal")
    assert set(watchers) < set(ROLES)
    rehearsal = PATH_VALUES["rehearsal_id"]  # unknown: a watcher learns 404, others 403 first
    for role in ROLES:
        client, _ = world.browser(role)
        page = client.get(f"/rehearsal/{rehearsal}/", follow_redirects=False)
        with pytest.raises(WebSocketDenialResponse) as socket, client.websocket_connect(
                f"/rehearsal/{rehearsal}", headers={"origin": "http://testserver"}):
            pass
        expected = 404 if role in watchers else 403
        assert page.status_code == expected, (role, page.status_code, page.text)
        assert socket.value.status_code == expected, (role, socket.value.status_code)
        if role not in watchers:
            assert "may not watch" in page.json()["detail"]
