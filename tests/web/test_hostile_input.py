"""Hostile numbers, duplicate keys, cursors and times are 4xx problems naming where,
never 500s or silently changed values."""

from __future__ import annotations

import json

import pytest

from .conftest import World

READERS = ("/api/validate", "/api/missions", "/api/import", "/api/read")


def _orders_text(world: World) -> str:
    orders = world.client("operator").get("/api/missions/search-and-sample").json()["orders"]
    orders["id"] = "hostile"
    return json.dumps(orders)


@pytest.mark.parametrize("number", ["1e999", "-1e999", "Infinity", "-Infinity", "NaN"])
def test_non_finite_numbers_are_refused_with_their_path(world: World, number: str) -> None:
    text = _orders_text(world)
    assert '"pd": 0.8' in text
    body = text.replace('"pd": 0.8', f'"pd": {number}', 1).encode()
    client = world.client("operator")
    for route in READERS:
        response = client.post(route, content=body, headers={"content-type": "application/json"})
        assert response.status_code == 422, (route, response.text)
        assert response.headers["content-type"].startswith("application/problem+json")
        assert response.json()["errors"][0]["path"] == "$.goals[0].params.pd", route
    assert client.get("/api/missions/hostile").status_code == 404


def test_non_finite_polygon_coordinate_is_refused(world: World) -> None:
    orders = json.loads(_orders_text(world))
    orders["areas"][0]["polygon"][1][0] = 1e308
    text = json.dumps(orders).replace("1e+308", "1e999")
    for route in READERS:
        response = world.client("operator").post(
            route, content=text.encode(), headers={"content-type": "application/json"})
        assert response.status_code == 422, (route, response.text)
        assert response.json()["errors"][0]["path"] == "$.areas[0].polygon[1][0]", response.text


def test_duplicate_keys_are_refused_by_every_reader(world: World) -> None:
    text = _orders_text(world)
    body = (text[:-1] + ', "title": "again"}').encode()
    for route in READERS:
        response = world.client("operator").post(
            route, content=body, headers={"content-type": "application/json"})
        assert response.status_code == 422, (route, response.text)
        assert "twice" in response.json()["errors"][0]["message"]


def test_vehicle_profile_with_huge_number_is_refused_not_stored_as_null(world: World) -> None:
    admin = world.client("admin")
    orders = json.loads(_orders_text(world))
    vehicle = orders["vehicles"][0]
    vehicle["speed_mps"] = 1.5
    text = json.dumps(vehicle).replace('"speed_mps": 1.5', '"speed_mps": 1e999')
    response = admin.put(f"/api/vehicles/{vehicle['id']}", content=text.encode(),
                         headers={"content-type": "application/json"})
    assert response.status_code == 422, response.text
    assert response.json()["errors"][0]["path"] == "$.speed_mps"
    stored = admin.get("/api/vehicles").json()
    assert all(v.get("speed_mps") is not None or v["id"] != vehicle["id"] for v in stored)


def test_deeply_nested_body_is_refused(world: World) -> None:
    body = b'{"a":' * 100 + b"1" + b"}" * 100
    response = world.client("admin").put("/api/vehicles/x", content=body,
                                         headers={"content-type": "application/json"})
    assert response.status_code == 422
    assert "deeper" in response.json()["errors"][0]["message"]


@pytest.mark.parametrize("point", [[1e300, 1e300], [91, 0], [0, 181]])
def test_plan_problem_with_huge_coordinates_is_422(world: World, point: list[float]) -> None:
    response = world.client("operator").post(
        "/api/missions/search-and-sample/plan-problem", json={"start": point, "recovery": [0, 0]})
    assert response.status_code == 422, response.text


def test_negative_path_cursor_is_400(world: World) -> None:
    response = world.client("operator").get("/api/missions/search-and-sample/paths",
                                            params={"cursor": "LTE="})
    assert response.status_code == 400


@pytest.mark.parametrize("when", ["2020-01-01T00:00:00", "9999-12-31T23:59:59-05:00"])
@pytest.mark.parametrize("name", ["since", "until"])
def test_approval_times_without_zone_or_past_9999_are_422(world: World, name: str,
                                                          when: str) -> None:
    response = world.client("auditor").get("/api/approvals", params={name: when})
    assert response.status_code == 422, response.text
    assert response.json()["errors"][0]["path"] == f"$.{name}"
    ok = world.client("auditor").get("/api/approvals", params={name: "2020-01-01T00:00:00Z"})
    assert ok.status_code == 200


@pytest.mark.parametrize("quantity", ["energy_wh", "duration_s"])
def test_finite_costs_summing_past_the_largest_double_are_not_500(world: World,
                                                                  quantity: str) -> None:
    orders = json.loads(_orders_text(world))
    for goal in orders["goals"]:
        goal["cost"] = {quantity: 1.7e308}
    response = world.client("operator").post("/api/validate", json=orders)
    assert response.status_code == 200, response.text
    worst = response.json()["costs"][quantity]["worst"]
    assert worst > 1e308


def _with_pd(world: World, value: str) -> bytes:
    # Turtle: free-form params are typed by no field of the orders model.
    turtle = world.client("operator").get(
        "/api/missions/search-and-sample/export", params={"format": "turtle"}).text
    assert "key:pd 0.8" in turtle
    return turtle.replace("search-and-sample", "hostile").replace("key:pd 0.8", value).encode()


@pytest.mark.parametrize("value", [
    "key:pd 123456789012345678901234567890",
    'key:pd "INF"^^<http://www.w3.org/2001/XMLSchema#double>',
    'key:pd "NaN"^^<http://www.w3.org/2001/XMLSchema#double>',
])
def test_undigestible_free_form_numbers_in_turtle_are_422(world: World, value: str) -> None:
    client = world.client("operator")
    for route in ("/api/import", "/api/read"):
        response = client.post(route, content=_with_pd(world, value),
                               headers={"content-type": "text/turtle"})
        assert response.status_code == 422, (route, response.text)
        assert response.json()["errors"][0]["path"] == "$.goals[0].params", response.text
        assert response.json()["errors"][0]["message"].startswith("pd: "), response.text
    assert client.get("/api/missions/hostile").status_code == 404


def test_inexact_integer_in_json_orders_is_422_with_its_path(world: World) -> None:
    text = _orders_text(world)
    body = text.replace('"pd": 0.8', '"pd": 123456789012345678901234567890', 1)
    for route in READERS:
        response = world.client("operator").post(
            route, content=body.encode(), headers={"content-type": "application/json"})
        assert response.status_code == 422, (route, response.text)
        assert response.json()["errors"][0]["path"] == "$.goals[0].params", response.text
        assert response.json()["errors"][0]["message"].startswith("pd: "), response.text
    unknown = (text[:-1] + ', "x_later": 123456789012345678901234567890}').encode()
    response = world.client("operator").post(
        "/api/import", content=unknown, headers={"content-type": "application/json"})
    assert response.status_code == 422, response.text
    assert response.json()["errors"][0]["message"].startswith("x_later: "), response.text
    # A typed number field converts it to a double, as it always did.
    typed = text.replace('"energy_wh": 180.0', '"energy_wh": 123456789012345678901234567890', 1)
    assert typed != text
    response = world.client("operator").post(
        "/api/validate", content=typed.encode(), headers={"content-type": "application/json"})
    assert response.status_code == 200, response.text


@pytest.mark.parametrize("when", ["9999-12-31T23:59:59-14:00", "0001-01-01T00:00:00+14:00"])
@pytest.mark.parametrize("name", ["since", "until"])
def test_event_times_beyond_utc_years_are_422(world: World, name: str, when: str) -> None:
    response = world.client("auditor").get("/api/events", params={name: when})
    assert response.status_code == 422, response.text
    assert response.json()["errors"][0]["path"] == f"$.{name}"
    # Without a zone, still UTC as before.
    ok = world.client("auditor").get("/api/events", params={name: "2020-01-01T00:00:00"})
    assert ok.status_code == 200


def test_paths_of_a_version_number_beyond_any_row_is_422(world: World) -> None:
    # 2**63 overflowed SQLite's INTEGER inside the query: a 500.
    response = world.client("operator").get("/api/missions/search-and-sample/paths",
                                            params={"version": str(2**63)})
    assert response.status_code == 422, response.text
    assert response.json()["errors"][0]["path"] == "$.version"
