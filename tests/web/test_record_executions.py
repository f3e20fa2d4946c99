"""The record (approval) page's executions: each recorded execution of the version
stated as "approved, executed as path N, no deviation" or naming the deviation; vehicle logs
in IMC accepted by the API; the cited rehearsal's runs through the same execution checker."""

from __future__ import annotations

import base64
import json
import time

from countersign.export.rehearsal_log import rehearsal_runs
from countersign.orders.examples import example_bytes
from countersign.orders.reader import read_bytes
from countersign.rehearse.execution import check_execution, read_log
from countersign.verify.paths import iter_paths, paths_of

from ..export.test_execution_input import imc_run
from .approval_helpers import MISSION, approve, new_version, register_key
from .conftest import World
from .test_approvals_rehearsal import _stored_record

ORDERS = read_bytes(example_bytes("search-and-sample"), "exemplar").orders


def _path(outcomes: tuple[str, ...]):  # type: ignore[no-untyped-def]
    graph, counts = paths_of(ORDERS)
    assert counts is not None
    return next(p for p in iter_paths(graph, counts) if p.outcomes == outcomes)


def test_the_record_states_each_execution_and_the_rehearsal(world: World) -> None:
    number = new_version(world)
    digest = _stored_record(world, number)
    operator = world.client("operator")
    submitted = operator.post(f"/api/missions/{MISSION}/versions/{number}/submit",
                              json={"rehearsal": digest})
    assert submitted.status_code == 201, submitted.text
    supervisor = world.client("supervisor")
    approval = approve(world, supervisor, register_key(supervisor), submitted.json()["id"])
    base = f"/api/missions/{MISSION}/versions/{number}/executions"
    path = _path(("violate", "succeed", "succeed"))
    # After the approval and within the clock skew of now (times are checked).
    imc = imc_run(path.goals, path.outcomes, path.terminal, t0=time.time(), step_s=30)
    recorded = operator.post(base, json={"data_base64": base64.b64encode(imc).decode()})
    assert recorded.status_code == 201, recorded.text
    assert recorded.json()["format"] == "imc" and recorded.json()["path"] == path.index
    skipped = "".join(json.dumps({"goal": g, "outcome": "succeed"}) + "\n"
                      for g in ("G1", "G3", "G4", "G5"))
    assert operator.post(base, json={"log": skipped, "format": "ndjson"}).status_code == 201
    assert operator.post(base, json={"log": skipped, "data_base64": "AA=="}
                         ).status_code == 422
    assert operator.post(base, json={"data_base64": "***"}).status_code == 422
    assert operator.post(base, json={"data_base64": "VP4AAAAA"}).status_code == 422

    page = world.client("auditor").get(f"/api/approvals/{approval['id']}/executions")
    assert page.status_code == 200, page.text
    body = page.json()
    statements = [e["statement"] for e in body["executions"]]
    # The IMC run has times but no readings of C1-C7: not "no deviation".
    assert statements[0].startswith(f"approved, executed as path {path.index}, unverified: "
                                    "no readings for C1")
    assert statements[1].startswith("approved, executed with 1 deviation(s): SKIPPED-GOAL "
                                    "at step 2: G2 was skipped")
    assert [e["log_index"] for e in body["executions"]] == sorted(
        e["log_index"] for e in body["executions"])
    # The log entry names the source format of the IMC run.
    entries = world.client("auditor").get("/api/log/entries").json()
    sources = [json.loads(e["entry"])["event"]["detail"].get("source")
               for e in entries if json.loads(e["entry"])["event"]["kind"] ==
               "execution.recorded"]
    assert sources[0] == {"format": "imc", "notes": []}

    # The rehearsal went through the checker: each run's verdict, its claimed path agreeing.
    runs = body["rehearsal"]
    assert runs, body
    for run in runs:
        verdict = run["verdict"]
        assert verdict["format"] == "rehearsal"
        assert verdict["ok"] or verdict["deviations"] or verdict["status"] == "unverified", \
            verdict
        if verdict["ok"] and run["claimed_path"] is not None:
            assert verdict["path"] == run["claimed_path"]
    assert any(run["verdict"]["path"] for run in runs), runs
    assert world.client("operator").get(
        f"/api/approvals/{approval['id']}/executions").status_code == 403


def test_a_rehearsal_record_converts_to_the_execution_log_of_each_run() -> None:
    path = _path(("violate", "succeed", "succeed"))
    record = {"runs": [{"path_index": path.index, "goals": list(path.goals),
                        "outcomes": list(path.outcomes), "terminal": path.terminal}],
              "events": [{"t": 0, "kind": "run"},
                         {"t": 0, "kind": "goal", "goal": "G1"},
                         {"t": 100, "kind": "outcome", "goal": "G1",
                          "data": {"outcome": "violate", "position": [0, 0, 30.0],
                                   "energy_wh": 40.0}},
                         {"t": 100, "kind": "goal", "goal": "G4"},
                         {"t": 300, "kind": "outcome", "goal": "G4",
                          "data": {"outcome": "succeed", "position": [0, 0, 25.0],
                                   "energy_wh": 60.0}},
                         {"t": 300, "kind": "goal", "goal": "G5"},
                         {"t": 500, "kind": "outcome", "goal": "G5",
                          "data": {"outcome": "succeed", "position": [0, 0, 14.0],
                                   "energy_wh": 10.0}}]}
    (run,) = rehearsal_runs(record)
    steps = read_log(run.ndjson)
    assert (steps[2].start, steps[2].time, steps[2].readings) == (
        "300", "500", {"depth_m": 14.0, "energy_wh": 110.0})
    verdict = check_execution(ORDERS, steps)
    assert [d.code for d in verdict.deviations] == ["CONSTRAINT"]  # C7: depth_m >= 20 at G5
    assert {u.quantity: (u.source, u.used) for u in verdict.usage} == {
        "energy_wh": ("readings", 110.0), "duration_s": ("timestamps", 500.0)}
    # Without events (or with some dropped) the run's goals and outcomes still check.
    (bare,) = rehearsal_runs(dict(record, events_dropped=3))
    assert check_execution(ORDERS, read_log(bare.ndjson)).path == path.index


def test_a_replayed_rehearsal_is_checked_as_the_path_it_replayed() -> None:
    """A real (headless) rehearsal replaying path 17: its record, through the execution
    checker, is path 17 with no deviation; the simulated times and energy are measured."""
    from countersign.rehearse.manager import Rehearsal, RehearsalOptions

    rehearsal = Rehearsal(ORDERS, owner="1", headless=True,
                          options=RehearsalOptions(source="replay", path_index=17, seed=1))
    rehearsal.run_headless(max_wall_s=60)
    (run,) = rehearsal_runs(rehearsal.stop().to_json())
    verdict = check_execution(ORDERS, read_log(run.ndjson))
    assert (run.claimed_path, verdict.path, verdict.deviations) == (17, 17, ())
    assert {u.quantity: u.source for u in verdict.usage} == {"energy_wh": "readings",
                                                             "duration_s": "timestamps"}
