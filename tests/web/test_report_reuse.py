"""A description edit is answered from the previous report's parts: the report is
exactly what a full validation gives, and the checks are not run again."""

from __future__ import annotations

from typing import Any

import pytest

from countersign.orders.model import Orders
from countersign.verify import report as verify_report
from countersign.verify import validate
from countersign.web.routes.schemas import ReportOut

from .conftest import World
from .described import assert_described

EXAMPLE = "search-and-sample"


def test_a_description_edit_reuses_the_report_and_equals_a_full_validation(
    world: World, monkeypatch: pytest.MonkeyPatch
) -> None:
    world.database.reports.clear()
    calls: list[str] = []

    def counting(orders: Orders, *args: Any, **kwargs: Any) -> Any:
        if orders.id == "reuse":
            calls.append(orders.id)
        return validate(orders, *args, **kwargs)

    monkeypatch.setattr(verify_report, "validate", counting)
    client = world.client("operator")
    orders = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]
    orders["id"] = "reuse"
    orders["title"] = "Reuse"
    created = client.post("/api/missions", json=orders)
    assert created.status_code in (200, 201), created.text
    first = client.get("/api/missions/reuse/report").json()
    assert calls == ["reuse"]

    orders["description"] = "A new description, read by no check."
    orders["goals"][0]["description"] = "So is this one."
    etag = client.get("/api/missions/reuse").headers["etag"]
    edited = client.put("/api/missions/reuse/draft", json={"orders": orders},
                        headers={"If-Match": etag})
    assert edited.status_code == 200, edited.text
    report = client.get("/api/missions/reuse/report").json()
    assert calls == ["reuse"]  # not validated again
    full = validate(Orders.model_validate(orders)).to_json()
    assert report == full
    assert report["digest"] != first["digest"]
    assert_described(ReportOut, full)  # the OpenAPI document's report is the whole report

    # A change that a check reads is validated in full.
    orders["goals"][0]["title"] = "Renamed goal"
    etag = client.get("/api/missions/reuse").headers["etag"]
    client.put("/api/missions/reuse/draft", json={"orders": orders}, headers={"If-Match": etag})
    report = client.get("/api/missions/reuse/report").json()
    assert calls == ["reuse", "reuse"]
    assert report == validate(Orders.model_validate(orders)).to_json()
