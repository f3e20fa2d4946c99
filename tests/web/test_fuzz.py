"""Schemathesis against the OpenAPI document: no 5xx for any operation.

1. Every operation alone, with a bounded number of generated requests, also checked against
   its response schema.
2. Stateful: schemathesis' state machine over the document's links (web/openapi_links.py: a
   mission listed or created, then read, versioned, submitted, reviewed, decided...) and those
   it infers, a bounded number of short scenarios; every response must be a non-5xx.

Both start from seeded states (SEEDS): missions with versions, a pending submission and a signed
approval, made through the API before any fuzzing. The listings then hand the state machine
real ids to follow, and two in three single-operation examples (chosen by a hash of the case,
so a failing one replays the same) take their path ids from the seeds: generated ids alone only
ever reach a 404, and a 500 planted in getVersion went unnoticed.

Each operation is called with an API token of a role that may call it (the reviewed table,
roles_reviewed.py), so generated requests reach the handlers instead of stopping at a 403; and
then, with fewer examples, with every role's token and with none."""

from __future__ import annotations

import os
import tempfile
import zlib
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import pytest
import schemathesis
from fastapi.dependencies.models import Dependant
from fastapi.dependencies.utils import get_dependant
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, settings
from schemathesis.checks import not_a_server_error, response_schema_conformance

from countersign.approvals import dsse
from countersign.orders.examples import load_example
from countersign.settings import Settings
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.store.missions import create_mission
from countersign.web.app import create_app
from countersign.web.deps import current_principal

from . import lazy_coverage
from .approval_helpers import Signer as _Signer
from .approval_helpers import sign_prepared
from .roles_reviewed import REVIEWED_ROLES

ROLES = ("operator", "supervisor", "auditor", "admin")
# Operations that end the fuzzers' own credentials or accounts: called by the single-operation
# run only (whose tokens they cannot reach: wrong password, another role), never by scenarios.
# A loaded two-core machine: the first validation starts the pool's processes (not a hang).
REQUEST_TIMEOUT_S = 120
# pytest-timeout guards against hangs. One generated test of this module sends thousands of
# cases (planning and campaign operations validate and plan each): ~50 s on a quiet machine,
# over the suite's 300 s when the machine is loaded ten times over. A hang still ends.
pytestmark = pytest.mark.timeout(1800)
ENDS_CREDENTIALS = ("changePassword", "logout", "updateUser", "revokeToken")
# Examples per operation and scenario, times this: CI runs 1; a longer run is e.g.
# `COUNTERSIGN_FUZZ_SCALE=4 pytest tests/web/test_fuzz.py`.
SCALE = max(1, int(os.environ.get("COUNTERSIGN_FUZZ_SCALE", "1")))


def _password(role: str) -> str:
    return f"Fz9-{role}-generated-Qp4"


def _app() -> Any:
    data = Path(tempfile.mkdtemp(prefix="countersign-fuzz-"))
    url = f"sqlite:///{data / 'fuzz.db'}"
    return create_app(Settings(data_dir=data, database_url=url), Database(url))


def _tokens(app: Any) -> dict[str, str]:
    database: Database = app.state.database
    tokens = {}
    with database.session() as db:
        for role in ROLES:
            user = create_user(db, username=f"fuzz-{role}", role=role, password=_password(role),
                               signer=database.log_signer)
            tokens[role] = create_token(db, user=user, name="fuzz", signer=database.log_signer)[1]
            if role == "operator":
                for example in SEEDED_EXAMPLES:
                    create_mission(db, orders=load_example(example), author=user,
                                   signer=database.log_signer)
    return tokens


# Missions seeded (more than one: generated requests may delete some), each with versions 1
# and 2; the first has version 1 approved and version 2 awaiting a decision.
SEEDED_EXAMPLES = ("search-and-sample", "harbor-approach-survey", "transect-survey")


def _seed(app: Any, tokens: dict[str, str]) -> dict[str, list[str]]:
    """Real ids by path parameter name, made through the API as users would."""
    client = TestClient(app)

    def call(role: str, method: str, url: str, **kwargs: Any) -> Any:
        response = client.request(method, url, headers={
            "Authorization": f"Bearer {tokens[role]}"}, **kwargs)
        assert response.status_code < 300, (url, response.text)
        return response.json()

    missions = [m["id"] for m in call("operator", "GET", "/api/missions")["items"]]
    for mission in missions:
        for _ in range(2):
            call("operator", "POST", f"/api/missions/{mission}/versions")
    approved, pending = (call("operator", "POST",
                              f"/api/missions/{missions[0]}/versions/{n}/submit") for n in (1, 2))
    key = dsse.generate_key()
    key_id = call("supervisor", "POST", "/api/keys", json={
        "public_key": dsse.public_text(key), "name": "fuzz", "password": _password("supervisor")
    })["key_id"]
    signer = _Signer(key, key_id)
    prepared = call("supervisor", "POST", f"/api/submissions/{approved['id']}/statement",
                    json={"decision": "approved", "reason": "", "key_id": key_id})
    approval = call("supervisor", "POST", f"/api/submissions/{approved['id']}/decision", json={
        "envelope": sign_prepared(prepared, signer), "password": _password("supervisor")})
    return {"mission_id": missions, "number": ["1", "2"], "key_id": [key_id],
            "submission_id": [str(approved["id"]), str(pending["id"])],
            "approval_id": [str(approval["id"])]}


# The app is made when the module is collected (its OpenAPI document makes the tests); its
# users and seeded objects when the first test runs (_seeded), so that a run that deselects
# these tests (pytest -m "not slow") does not pay for them.
APP = _app()
TOKENS: dict[str, str] = {}
SEEDS: dict[str, list[str]] = {}
# Operations that take seeded ids in the single-operation run: the reads and the workflow's
# cheap steps. The others reach real objects through the workflow scenarios; given real ids here
# they would destroy the seeds (deleteMission) or start real work for each example (rehearsals,
# plans, packages: minutes on a loaded machine).
SEEDED_OPERATIONS = ("getMission", "getVersion", "getReport", "listPaths", "getMissionStanding",
                     "reviewVersion", "getSubmission", "getApproval", "listRehearsalRecords",
                     "createVersion", "submitVersion", "withdrawSubmission", "prepareDecision",
                     "prepareRevocation")
# Each operation's coverage cases are made when its test runs, not in every process that
# collects this module (tests/web/lazy_coverage.py).
lazy_coverage.install()
schema = schemathesis.openapi.from_asgi("/api/openapi.json", APP)


def _operation_id(case: schemathesis.Case) -> str:
    operation_id: str = case.operation.definition.raw.get("operationId", "")
    return operation_id


def _role(case: schemathesis.Case) -> str:
    """The first role allowed to call the operation ("" for anonymous ones); an operation
    missing from the table gets the operator's (test_roles.py names it)."""
    operation_id = _operation_id(case)
    if operation_id in ENDS_CREDENTIALS:
        return "operator" if operation_id != "updateUser" else "supervisor"
    return next((r for r in REVIEWED_ROLES.get(operation_id, ("operator",)) if r in ROLES), "")


def _headers(case: schemathesis.Case) -> dict[str, str]:
    """A token of the operation's first allowed role (_role), none for anonymous ones."""
    role = _role(case)
    return {**(case.headers or {}), **({"Authorization": f"Bearer {TOKENS[role]}"}
                                       if role else {})}


@pytest.fixture(scope="module", autouse=True)
def _seeded() -> Iterator[None]:
    """Users, tokens and seeded objects before the first test; generated requests may start
    rehearsals (viser servers): stop them at the end."""
    TOKENS.update(_tokens(APP))
    SEEDS.update(_seed(APP, TOKENS))
    yield
    APP.state.rehearsals.shutdown()


def _with_seeded_ids(case: schemathesis.Case) -> None:
    """Two cases in three (by a stable hash of the generated ones) address seeded objects."""
    operation_id = _operation_id(case)
    parameters = case.path_parameters or {}
    known = [name for name in parameters if name in SEEDS]
    if not known or operation_id not in SEEDED_OPERATIONS:
        return
    pick = zlib.crc32(repr(sorted(parameters.items())).encode())
    if pick % 3 == 0:
        return
    for name in known:
        choices = SEEDS[name]
        parameters[name] = choices[(pick >> 1) % len(choices)]


@schema.parametrize()
@settings(max_examples=10 * SCALE, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
def test_api_has_no_server_errors(case: schemathesis.Case) -> None:
    case.headers = _headers(case)
    _with_seeded_ids(case)
    case.call_and_validate(checks=[not_a_server_error, response_schema_conformance],
                           timeout=REQUEST_TIMEOUT_S)


# The operations test_no_role_meets_a_server_error has sent a case of.
_SENT: set[str] = set()


def _reaching_roles(operation_id: str) -> set[str]:
    """The callers whose request reaches the operation's handler: its allowed roles, or every
    caller of an anonymous operation. Any other caller is refused by the route's role check,
    which FastAPI runs before it reads the path, query or body: a refusal is the same
    whatever the case holds."""
    allowed = REVIEWED_ROLES.get(operation_id, ("operator",))
    return {*ROLES, "anonymous"} if "anonymous" in allowed else set(allowed)


def _api_routes(routes: Iterable[Any]) -> Iterator[APIRoute]:
    for route in routes:
        if isinstance(route, APIRoute):
            yield route
        included = getattr(route, "original_router", None)  # an included router's routes
        if included is not None:
            yield from _api_routes(included.routes)


def _reads_the_caller(dependant: Dependant) -> bool:
    return any(d.call is current_principal or _reads_the_caller(d)
               for d in dependant.dependencies)


def test_every_operation_is_found_among_the_routes() -> None:
    """READS_THE_CALLER walks the app's routes through FastAPI's included routers (their
    `original_router`, not a documented attribute): an operation it missed would lose its
    second role silently, so a change of FastAPI's structure fails here instead."""
    found = {route.operation_id for route in _api_routes(APP.routes)}
    documented = {operation["operationId"] for path in APP.openapi()["paths"].values()
                  for operation in path.values() if "operationId" in operation}
    assert documented <= found, sorted(documented - found)


# Operations whose handler (its own parameters, not the route's role check and rate limit)
# reads who is calling: only there may a second role that the operation serves get another
# answer for the same case than the role test_api_has_no_server_errors sent it with.
READS_THE_CALLER = {
    route.operation_id for route in _api_routes(APP.routes)
    if route.operation_id is None
    or _reads_the_caller(get_dependant(path=route.path_format, call=route.endpoint))}


def _refusal_roles(case: schemathesis.Case) -> list[str]:
    """The roles test_no_role_meets_a_server_error sends this case with: all but the one
    test_api_has_no_server_errors sends it with (the operation's first allowed role, or
    anonymous) for the operation's first case, so that every role, refused or not, meets every
    operation; then, where the handler reads who is calling (READS_THE_CALLER), one of those
    whose request reaches it (_reaching_roles), chosen by a stable hash of the case, so that
    every such case meets a second role the handler serves. Elsewhere no later case is sent
    again: a refused role's answer does not depend on the case, and a handler that does not
    read the caller answers every role it serves as it answered the first."""
    already = _role(case) or "anonymous"
    others = [role for role in (*ROLES, "anonymous") if role != already]
    label = case.operation.label
    first = label not in _SENT
    _SENT.add(label)
    if first or SCALE > 1:
        return others
    operation_id = _operation_id(case)
    if operation_id not in READS_THE_CALLER:
        return []
    served = [role for role in others if role in _reaching_roles(operation_id)]
    if not served:
        return []
    key = repr((case.path_parameters, case.query, case.body))
    return [served[zlib.crc32(key.encode()) % len(served)]]


@schema.exclude(operation_id=list(ENDS_CREDENTIALS)).parametrize()
@settings(max_examples=SCALE, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
def test_no_role_meets_a_server_error(case: schemathesis.Case) -> None:
    """Every operation with the other roles' tokens and with none, so that refusals too (403s,
    401s, the checks before a role check) are never a 5xx. An operation's first case goes to
    every other role and to none; each later case, where the handler reads who is calling, to
    one other role it serves (_refusal_roles), not to each: sent four times, the coverage
    phase's thousands of cases per operation (3,700 for the draft's PUT) made this the suite's
    longest test, and sent to a refused role they met the same role check again and again (two
    operator-only operations spent 40 s so). COUNTERSIGN_FUZZ_SCALE above 1 sends every case
    with every role."""
    _with_seeded_ids(case)
    plain = {k: v for k, v in (case.headers or {}).items() if k.lower() != "authorization"}
    for role in _refusal_roles(case):
        case.headers = {**plain, **({"Authorization": f"Bearer {TOKENS[role]}"}
                                    if role != "anonymous" else {})}
        case.call_and_validate(checks=[not_a_server_error], timeout=REQUEST_TIMEOUT_S)


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
    max_examples=15 * SCALE, stateful_step_count=5, deadline=None,
    suppress_health_check=list(HealthCheck))

# The approval workflow alone: with every operation in play, a scenario of a few steps rarely
# follows a listing to a version or an approval (a 500 planted in getVersion went unseen), so
# these scenarios choose only among the operations on the way from a mission to its decision.
WORKFLOW = ("listMissions", "getMission", "createVersion", "getVersion", "reviewVersion",
            "submitVersion", "listSubmissions", "getSubmission", "prepareDecision",
            "withdrawSubmission", "listApprovals", "getApproval", "prepareRevocation",
            "getReport", "listPaths", "getMissionStanding", "exportMission", "downloadPackage")


class WorkflowScenarios(schema.include(operation_id=list(WORKFLOW)).as_state_machine()):  # type: ignore[misc]
    get_call_kwargs = Scenarios.get_call_kwargs
    validate_response = Scenarios.validate_response


TestWorkflowScenarios = WorkflowScenarios.TestCase
TestWorkflowScenarios.settings = settings(
    max_examples=20 * SCALE, stateful_step_count=8, deadline=None,
    suppress_health_check=list(HealthCheck))
