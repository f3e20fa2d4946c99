"""The report service owns the single-flight cache and the validator: one per
database, injected, no module state."""

from __future__ import annotations

import threading
from typing import Any

import pytest

from countersign.orders.canonical import digest
from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.store.db import Database
from countersign.store.report_service import ReportService, validate_here
from countersign.verify import fingerprint
from countersign.verify.fingerprint import checker_fingerprint

OTHER = "sha256:" + "0" * 64


def test_many_requests_for_one_digest_validate_once() -> None:
    orders = load_example("search-and-sample")
    calls: list[str] = []
    release = threading.Event()

    def slow(given: Orders) -> dict[str, Any]:
        calls.append(given.id)
        release.wait(60)
        return {"digest": "sha256:x", "mission": given.id, "checker": checker_fingerprint()}

    service = ReportService(validator=slow)
    answers: list[dict[str, Any]] = []
    threads = [threading.Thread(target=lambda: answers.append(service.report("k", orders)))
               for _ in range(4)]
    for thread in threads:
        thread.start()
    release.set()
    for thread in threads:
        thread.join(60)
    assert calls == ["search-and-sample"]
    assert len(answers) == 4 and all(a == answers[0] for a in answers)


def test_each_database_has_its_own_service(tmp_path: Any) -> None:
    first = Database(f"sqlite:///{tmp_path / 'a.db'}")
    second = Database(f"sqlite:///{tmp_path / 'b.db'}")
    assert first.reports is not second.reports
    orders = load_example("search-and-sample")
    fake = {"digest": "from-first", "checker": checker_fingerprint()}
    first.reports.validator = lambda given: fake
    assert first.reports.report("k", orders) == fake
    # The other database's service saw nothing and validates with the real checks.
    assert second.reports.report(digest(orders), orders) == validate_here(orders)
    first.engine.dispose()
    second.engine.dispose()


def test_reports_cached_under_another_fingerprint_are_not_reused(
        monkeypatch: pytest.MonkeyPatch) -> None:
    orders = load_example("search-and-sample")
    calls: list[str] = []

    def counting(given: Orders) -> dict[str, Any]:
        calls.append(fingerprint.checker_fingerprint())
        return {"digest": "k", "checker": fingerprint.checker_fingerprint()}

    service = ReportService(validator=counting)
    service.report("k", orders)
    service.report("k", orders)
    monkeypatch.setattr(fingerprint, "checker_fingerprint", lambda: OTHER)
    assert service.report("k", orders)["checker"] == OTHER
    assert calls == [checker_fingerprint(), OTHER]


def test_a_report_of_other_checks_from_the_validator_is_made_again_here() -> None:
    """A pool process started from replaced files runs other checks than this process."""
    orders = load_example("search-and-sample")
    service = ReportService(validator=lambda given: {"digest": "k", "checker": OTHER})
    assert service.report(digest(orders), orders) == validate_here(orders)
