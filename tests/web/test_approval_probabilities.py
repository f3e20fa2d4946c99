"""The outcome probabilities are on the review and inside the signed statement."""

from __future__ import annotations

from typing import Any

from countersign.web.routes.schemas import ProbabilitiesOut, ReportOut

from .approval_helpers import MISSION, new_version, prepare, register_key, sign_prepared, submit
from .conftest import PASSWORD, World
from .described import assert_described

P = {"succeed": 0.8, "fail": 0.15, "violate": 0.05}


def _with_probabilities(world: World) -> dict[str, Any]:
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    for goal in orders["goals"]:
        goal["p"] = P
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    return orders


def test_review_and_statement_carry_the_probabilities(world: World) -> None:
    _with_probabilities(world)
    number = new_version(world)
    review = world.client("auditor").get(
        f"/api/missions/{MISSION}/versions/{number}/review").json()
    figures = review["probabilities"]
    assert figures["exact"] is True
    complete = figures["terminals"]["COMPLETE"]
    assert complete["min"] == complete["max"] == 0.8  # every path ends at G5: 0.8 succeeds
    # The review shows the version's report figures, which the models describe exactly.
    report = world.client("auditor").get(f"/api/missions/{MISSION}/report").json()
    assert report["probabilities"] == figures and report["digest"] == review["digest"]
    assert_described(ProbabilitiesOut, figures)
    assert_described(ReportOut, report)
    page = world.client("auditor").get(f"/api/missions/{MISSION}/paths",
                                       params={"version": number, "limit": 50}).json()
    assert page["items"] and all(item["probability"] is not None for item in page["items"])

    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, number)
    prepared = prepare(supervisor, submission, signer)
    assert prepared["statement"]["predicate"]["probabilities"] == figures
    envelope = sign_prepared(prepared, signer)
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": envelope, "password": PASSWORD})
    assert response.status_code == 201, response.text


def test_orders_without_probabilities_sign_no_probabilities(world: World) -> None:
    number = new_version(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = prepare(supervisor, submit(world, number), signer)
    assert "probabilities" not in prepared["statement"]["predicate"]


def test_the_paths_explorer_gives_each_path_its_probability(world: World) -> None:
    client = world.client("supervisor")
    assert client.get(f"/api/missions/{MISSION}/paths").json()["items"][0]["probability"] is None
    _with_probabilities(world)
    page = client.get(f"/api/missions/{MISSION}/paths", params={"limit": 100}).json()
    assert abs(sum(item["probability"] for item in page["items"]) - 1) < 1e-9
    streamed = client.get(f"/api/missions/{MISSION}/paths", params={"format": "ndjson"})
    assert '"probability":' in streamed.text.splitlines()[0]
