from __future__ import annotations

from countersign.plan.examples import gravitas_data

from .conftest import World


def test_plan_route_solves_gravitas_and_drafts_valid_orders(world: World) -> None:
    client = world.client("operator")
    answer = client.post("/api/plan", json=gravitas_data()).json()
    assert answer["feasible"] is True and set(answer["order"]) == {"LL", "UR", "LR"}
    replanned = client.post("/api/plan", json=gravitas_data(replan=True)).json()
    assert replanned["order"] == ["LR"]
    report = client.post("/api/validate", json=replanned["orders"]).json()
    assert not [f for f in report["findings"] if f["code"] == "BUDGET"]


def test_plan_problem_from_a_mission(world: World) -> None:
    client = world.client("operator")
    problem = client.post("/api/missions/search-and-sample/plan-problem", json={
        "start": [36.80, -121.79], "recovery": [36.80, -121.79], "areas": ["A", "B"]})
    assert problem.status_code == 200, problem.text
    body = problem.json()
    assert body["format"] == "countersign.plan/1"
    assert [a["id"] for a in body["areas"]] == ["A", "B"]
    assert client.post("/api/plan", json=body).json()["feasible"] is True


def test_plan_bad_input_is_a_problem_document(world: World) -> None:
    client = world.client("operator")
    bad = client.post("/api/plan", json={"format": "countersign.plan/1", "level": 3})
    assert bad.status_code == 422 and bad.json()["errors"]
    assert world.client("auditor").post("/api/missions/search-and-sample/plan-problem",
                                         json={"start": [0, 0], "recovery": [0, 0]}
                                         ).status_code == 403
