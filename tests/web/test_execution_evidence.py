"""Executions through the API: a log without times or readings is recorded as "unverified"
and the record says what was and was not evidenced and who uploaded it; absurd times and JSON
nested too deep are 422 naming where; checking a log does not hold the write lock."""

from __future__ import annotations

import json
import threading
import time
from typing import Any

import pytest

from countersign.web.routes import executions as route

from ..export.execution_logs import evidenced_log
from ..export.test_execution_input import imc_run
from .approval_helpers import MISSION, approve, new_version, register_key
from .conftest import World

RUN = (("G1", "violate"), ("G4", "succeed"), ("G5", "succeed"))


def _approved(world: World) -> tuple[str, int]:
    number = new_version(world)
    submitted = world.client("operator").post(
        f"/api/missions/{MISSION}/versions/{number}/submit")
    assert submitted.status_code == 201, submitted.text
    supervisor = world.client("supervisor")
    approval = approve(world, supervisor, register_key(supervisor), submitted.json()["id"])
    return f"/api/missions/{MISSION}/versions/{number}/executions", int(approval["id"])


def test_without_evidence_the_record_says_unverified_and_what_is_missing(world: World) -> None:
    base, approval = _approved(world)
    operator = world.client("operator")
    bare = "".join(json.dumps({"goal": g, "outcome": o}) + "\n" for g, o in RUN)
    posted = operator.post(base, json={"log": bare})
    assert posted.status_code == 201, posted.text
    assert (posted.json()["status"], posted.json()["ok"]) == ("unverified", False)
    complete = operator.post(base, json={"log": evidenced_log(RUN)})
    assert complete.status_code == 201 and complete.json()["status"] == "no-deviation", \
        complete.text
    path = complete.json()["path"]

    page = world.client("auditor").get(f"/api/approvals/{approval}/executions").json()
    unverified, verified = page["executions"]
    assert unverified["statement"] == (
        f"approved, executed as path {path}, unverified: no start and end times for steps "
        "1, 2, 3; no readings for C1, C2, C3, C4, C5, C6, C7")
    assert (unverified["ok"], unverified["status"]) == (False, "unverified")
    assert unverified["evidence"]["constraints_unread"] == [f"C{i}" for i in range(1, 8)]
    assert unverified["actor"] == verified["actor"] == "operator1"  # who uploaded it
    assert verified["statement"] == f"approved, executed as path {path}, no deviation"
    assert verified["evidence"]["timed"] and verified["evidence"]["gaps"] == []


def test_an_imc_log_of_a_real_run_after_the_approval_is_read_with_its_times(
        world: World) -> None:
    import base64

    from countersign.orders.examples import example_bytes
    from countersign.orders.reader import read_bytes
    from countersign.verify.paths import iter_paths, paths_of

    base, _ = _approved(world)
    orders = read_bytes(example_bytes("search-and-sample"), "exemplar").orders
    graph, counts = paths_of(orders)
    assert counts is not None
    path = next(p for p in iter_paths(graph, counts)
                if p.outcomes == ("violate", "succeed", "succeed"))
    # Starts after the approval and ends within the clock skew of now, whenever it runs.
    imc = imc_run(path.goals, path.outcomes, path.terminal, t0=time.time(), step_s=30)
    posted = world.client("operator").post(
        base, json={"data_base64": base64.b64encode(imc).decode()})
    assert posted.status_code == 201, posted.text
    assert posted.json()["evidence"]["timed"] is True
    old = imc_run(path.goals, path.outcomes, path.terminal)  # 2026-11-30: before approval
    refused = world.client("operator").post(
        base, json={"data_base64": base64.b64encode(old).decode()})
    assert refused.status_code == 422 and "before the orders were approved" in refused.text


@pytest.mark.parametrize(("time_text", "message"), [
    ("9999-12-31T23:59:59Z", "is in the future"),
    ("not-a-time", "is not an ISO 8601 time"),
    ("2000-01-01T00:00:00Z", "before the orders were approved"),
])
def test_absurd_times_are_422_naming_the_step(world: World, time_text: str,
                                              message: str) -> None:
    base, _ = _approved(world)
    step = json.loads(evidenced_log(RUN[:1]))
    step.pop("start")
    step["time"] = time_text
    posted = world.client("operator").post(base, json={"log": json.dumps(step) + "\n"})
    assert posted.status_code == 422, posted.text
    assert "step 1 (G1) time" in posted.text and message in posted.text
    backwards = evidenced_log(RUN).replace('"start": "20"', '"start": "5"')
    posted = world.client("operator").post(base, json={"log": backwards})
    assert posted.status_code == 422 and "must not run backwards" in posted.text


def test_json_nested_a_thousand_deep_is_422_not_500(world: World) -> None:
    base, _ = _approved(world)
    operator = world.client("operator")
    deep = '{"goal": "G1", "outcome": "succeed", "readings": ' + "[" * 1000 + "]" * 1000 + "}"
    in_log = operator.post(base, json={"log": deep + "\n"})
    assert in_log.status_code == 422 and "line 1" in in_log.text, in_log.text
    body = '{"log": "x", "format": ' + "[" * 1000 + "]" * 1000 + "}"
    in_body = operator.post(base, content=body, headers={"Content-Type": "application/json"})
    assert in_body.status_code == 422 and "nested" in in_body.text, in_body.text


def test_a_slow_check_does_not_hold_the_write_lock(world: World,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    base, _ = _approved(world)
    checking, written = threading.Event(), threading.Event()
    real = route.check_execution

    def slow_check(*args: Any, **kwargs: Any) -> Any:
        checking.set()
        # Holds the check until another writer has saved (or gives up, so that a broken
        # build fails instead of hanging).
        written.wait(timeout=120)
        return real(*args, **kwargs)

    monkeypatch.setattr(route, "check_execution", slow_check)
    results: dict[str, Any] = {}

    def upload() -> None:
        results["execution"] = world.client("operator").post(
            base, json={"log": evidenced_log(RUN)})

    uploader = threading.Thread(target=upload)
    uploader.start()
    assert checking.wait(timeout=120), "the check never started"
    # Another user's save while the check runs: it must complete, not wait for the check.
    saved = world.client("operator").post(f"/api/missions/{MISSION}/versions")
    results["saved_while_checking"] = not written.is_set()
    written.set()
    uploader.join(timeout=120)
    assert saved.status_code == 201, saved.text
    assert results["saved_while_checking"]
    assert results["execution"].status_code == 201, results["execution"].text
