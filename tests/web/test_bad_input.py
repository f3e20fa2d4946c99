from __future__ import annotations

from .conftest import World, count_rows


def test_oversized_body_is_refused(world: World) -> None:
    client = world.client("operator")
    response = client.post("/api/import", content=b"{" + b" " * (10 * 1024 * 1024) + b"}")
    assert response.status_code == 413
    assert response.headers["content-type"].startswith("application/problem+json")


def test_malformed_documents_are_4xx_problems(world: World) -> None:
    client = world.client("operator")
    cases = [b"{not json", b"[]", b"<AVCL><unclosed>", b"<!DOCTYPE x [<!ENTITY a 'b'>]><AVCL/>",
             b"", b'{"id": "x", "goals": [{"id": "G 1"}]}']
    for body in cases:
        response = client.post("/api/import", content=body)
        assert 400 <= response.status_code < 500, (body, response.status_code)
        assert response.json()["status"] == response.status_code
        assert "Traceback" not in response.text
    located = client.post("/api/import", content=b'{"id": "x", "goals": [{"id": "G 1"}]}')
    assert located.json()["errors"][0]["path"] == "$.goals[0].id"


def test_sql_metacharacters_are_plain_data(world: World) -> None:
    client = world.client("operator")
    nasty = "Robert'); DROP TABLE missions;--"
    orders = client.get("/api/missions/search-and-sample").json()["orders"]
    orders["id"] = "quoted"
    orders["title"] = nasty
    assert client.post("/api/missions", json=orders).status_code == 201
    assert client.get("/api/missions/quoted").json()["title"] == nasty
    found = client.get("/api/missions", params={"q": "'); DROP"}).json()["items"]
    assert [m["id"] for m in found] == ["quoted"]
    assert client.get("/api/missions", params={"q": "%"}).json()["items"] == []
    bad_id = client.get("/api/missions/' OR '1'='1")
    assert bad_id.status_code == 404
    assert count_rows(world.database, "SELECT count(*) FROM missions") == 2


def test_bad_cursor_and_unknown_routes(world: World) -> None:
    client = world.client("auditor")
    assert client.get("/api/missions", params={"cursor": "!!!"}).status_code == 400
    assert client.get("/api/nothing-here").status_code == 404


def test_unknown_fields_in_request_bodies_are_refused(world: World) -> None:
    client = world.client()
    response = client.post("/api/auth/login",
                           json={"username": "admin1", "password": "x", "remember": True})
    assert response.status_code == 422
    assert response.json()["errors"][0]["path"] == "$.remember"
    admin = world.client("admin")
    typo = admin.post("/api/users", json={"username": "eve", "role": "auditor",
                                          "password": "a long password", "rol": "admin"})
    assert typo.status_code == 422
