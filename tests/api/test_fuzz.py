"""Schemathesis against the OpenAPI document: no 5xx and no response that contradicts the
schema, for every operation, with a bounded number of generated requests."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

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


def _app_and_token() -> tuple[object, str]:
    data = Path(__import__("tempfile").mkdtemp(prefix="countersign-fuzz-"))
    url = f"sqlite:///{data / 'fuzz.db'}"
    database = Database(url)
    app = create_app(Settings(data_dir=data, database_url=url), database)
    with database.session() as db:
        user = create_user(db, username="fuzzer", role="operator", password="fuzzing password")
        create_mission(db, orders=load_example("search-and-sample"), author=user)
        token = create_token(db, user=user, name="fuzz")[1]
    return app, token


APP, TOKEN = _app_and_token()
schema = schemathesis.openapi.from_asgi("/api/openapi.json", APP)


@pytest.fixture(scope="module", autouse=True)
def _stop_rehearsals() -> Iterator[None]:
    """Generated requests may start rehearsals (viser servers): stop them at the end."""
    yield
    APP.state.rehearsals.shutdown()  # type: ignore[attr-defined]


@schema.parametrize()
@settings(max_examples=15, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
def test_api_has_no_server_errors(case: schemathesis.Case) -> None:
    case.headers = {**(case.headers or {}), "Authorization": f"Bearer {TOKEN}"}
    case.call_and_validate(checks=[not_a_server_error, response_schema_conformance])
