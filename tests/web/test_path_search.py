"""GET /api/missions/{id}/paths: a stored version's paths, and the search by goal and terminal
that the review's path list pages through."""

from __future__ import annotations

from .conftest import World

EXAMPLE = "search-and-sample"


def _all(client, **params: object) -> tuple[dict, list[dict]]:
    first = client.get(f"/api/missions/{EXAMPLE}/paths", params={"limit": 7, **params})
    assert first.status_code == 200, first.text
    page = first.json()
    items = list(page["items"])
    while page["next_cursor"]:
        page = client.get(f"/api/missions/{EXAMPLE}/paths",
                          params={"limit": 7, "cursor": page["next_cursor"], **params}).json()
        items += page["items"]
    return first.json(), items


def test_search_by_goal_and_terminal_pages_the_matches(world: World) -> None:
    client = world.client("supervisor")
    _, every = _all(client)
    assert len(every) == 75
    for params in ({"goal": "G3"}, {"terminal": "COMPLETE"}, {"goal": "G2", "terminal": "ABORT"}):
        first, found = _all(client, **params)
        expected = [p for p in every
                    if ("goal" not in params or params["goal"] in p["goals"])
                    and ("terminal" not in params or p["terminal"] == params["terminal"])]
        assert found == expected, params
        assert first["matching"] == len(expected) and first["count"] == 75
    assert len(_all(client, terminal="COMPLETE")[1]) == 25


def test_a_versions_paths_not_the_drafts(world: World) -> None:
    client = world.client("operator")
    assert client.post(f"/api/missions/{EXAMPLE}/versions").status_code == 201
    orders = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]
    orders["goals"][0]["next"]["fail"] = "ABORT"  # fewer paths in the draft
    saved = client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders},
                       headers={"If-Match": '"1"'})
    assert saved.status_code == 200
    draft = client.get(f"/api/missions/{EXAMPLE}/paths").json()
    version = client.get(f"/api/missions/{EXAMPLE}/paths", params={"version": 1}).json()
    assert version["count"] == 75 and draft["count"] < 75
    missing = client.get(f"/api/missions/{EXAMPLE}/paths", params={"version": 9})
    assert missing.status_code == 404


def test_unknown_search_terms_are_named(world: World) -> None:
    client = world.client("auditor")
    answer = client.get(f"/api/missions/{EXAMPLE}/paths", params={"goal": "G99"})
    assert answer.status_code == 400 and "G99" in answer.text
    answer = client.get(f"/api/missions/{EXAMPLE}/paths", params={"terminal": "NOWHERE"})
    assert answer.status_code == 400 and "NOWHERE" in answer.text
    answer = client.get(f"/api/missions/{EXAMPLE}/paths", params={"goal": "x" * 201})
    assert answer.status_code == 422
    streamed = client.get(f"/api/missions/{EXAMPLE}/paths",
                          params={"format": "ndjson", "goal": "G3"})
    assert streamed.status_code == 400
