"""Schemathesis against the OpenAPI document (issue 15 item 9): no 5xx for any operation.

1. Every operation alone, with a bounded number of generated requests, also checked against
   its response schema.
2. Stateful: schemathesis' state machine over the links it infers from the document (a mission
   created, then read, edited, versioned, submitted, reviewed...), a bounded number of short
   scenarios; every response must be a non-5xx.

Each operation is called with an API token of a role that may call it (the reviewed table,
roles_reviewed.py), so generated requests reach the handlers instead of stopping at a 403."""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.checks import not_a_server_error, response_schema_conformance

from countersign.orders.examples import load_example
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.store.missions import create_mission
from countersign.web.app import create_app
from countersign.web.settings import Settings

from .roles_reviewed import REVIEWED_ROLES

ROLES = ("operator", "supervisor", "auditor", "admin")
# Operations that end the fuzzers' own credentials or accounts: called by the single-operation
# run only (whose tokens they cannot reach: wrong password, another role), never by scenarios.
# A loaded two-core machine: the first validation starts the pool's processes (not a hang).
REQUEST_TIMEOUT_S = 120
ENDS_CREDENTIALS = ("changePassword", "logout", "updateUser", "revokeToken")


def _app_and_tokens() -> tuple[Any, dict[str, str]]:
    data = Path(tempfile.mkdtemp(prefix="countersign-fuzz-"))
    url = f"sqlite:///{data / 'fuzz.db'}"
    database = Database(url)
    app = create_app(Settings(data_dir=data, database_url=url), database)
    tokens = {}
    with database.session() as db:
        for role in ROLES:
            user = create_user(db, username=f"fuzz-{role}", role=role,
                               password=f"Fz9-{role}-generated-Qp4")
            tokens[role] = create_token(db, user=user, name="fuzz")[1]
            if role == "operator":
                create_mission(db, orders=load_example("search-and-sample"), author=user)
    return app, tokens


APP, TOKENS = _app_and_tokens()
schema = schemathesis.openapi.from_asgi("/api/openapi.json", APP)


def _headers(case: schemathesis.Case) -> dict[str, str]:
    """A token of the first role allowed to call the operation (none for anonymous ones); an
    operation missing from the table gets the operator's (test_roles.py names it)."""
    operation_id = case.operation.definition.raw.get("operationId", "")
    if operation_id in ENDS_CREDENTIALS:
        role = "operator" if operation_id != "updateUser" else "supervisor"
    else:
        role = next((r for r in REVIEWED_ROLES.get(operation_id, ("operator",))
                     if r in TOKENS), "")
    return {**(case.headers or {}), **({"Authorization": f"Bearer {TOKENS[role]}"}
                                       if role else {})}


@pytest.fixture(scope="module", autouse=True)
def _stop_rehearsals() -> Iterator[None]:
    """Generated requests may start rehearsals (viser servers): stop them at the end."""
    yield
    APP.state.rehearsals.shutdown()


@schema.parametrize()
@settings(max_examples=10, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
def test_api_has_no_server_errors(case: schemathesis.Case) -> None:
    case.headers = _headers(case)
    case.call_and_validate(checks=[not_a_server_error, response_schema_conformance],
                           timeout=REQUEST_TIMEOUT_S)


class Scenarios(schema.exclude(operation_id=list(ENDS_CREDENTIALS)).as_state_machine()):  # type: ignore[misc]
    def get_call_kwargs(self, case: schemathesis.Case) -> dict[str, Any]:
        return {"headers": _headers(case), "timeout": REQUEST_TIMEOUT_S}

    def validate_response(self, response: Any, case: schemathesis.Case,
                          additional_checks: Any = None, **kwargs: Any) -> None:
        # Stateful requests break schemas on purpose less often than they reach deep states:
        # the property here is the server's (never a 5xx); schemas are checked above.
        case.validate_response(response, checks=[not_a_server_error])


TestStatefulScenarios = Scenarios.TestCase
TestStatefulScenarios.settings = settings(
    max_examples=15, stateful_step_count=5, deadline=None,
    suppress_health_check=list(HealthCheck))
