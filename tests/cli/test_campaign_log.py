"""`countersign campaign run|cancel` append to the log as the web app does: the entries carry
the log signer's receipts, an audit bundle of the database verifies, and a receipt deleted
behind the app's back is named by the verifier."""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import select, text

from countersign.approvals.bundle import verify_bundle
from countersign.cli import main
from countersign.cli.server import open_database
from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import example_bytes
from countersign.orders.reader import read_bytes
from countersign.store import campaigns as store
from countersign.store.approvals.bundle import build_bundle
from countersign.store.tables import Event, LogEntry, LogReceipt

EXAMPLE = "search-and-sample"


@pytest.fixture
def data_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An embedded database of the command line's own, whatever the suite's environment."""
    for name in [k for k in os.environ if k.startswith("COUNTERSIGN_")]:
        monkeypatch.delenv(name)
    return tmp_path / "data"


def _bundle(data_dir: Path) -> dict[str, Any]:
    _, database = open_database(argparse.Namespace(data_dir=data_dir))
    assert database.log_signer is not None
    with database.session() as db:
        return build_bundle(db, signer=database.log_signer)


def _queued(data_dir: Path) -> str:
    """A campaign waiting for its jobs, made as the command line makes one."""
    _, database = open_database(argparse.Namespace(data_dir=data_dir))
    orders = read_bytes(example_bytes(EXAMPLE), EXAMPLE).orders
    with database.session() as db:
        return store.create(db, orders=orders_to_json(orders), orders_digest=digest(orders),
                            spec={"simulations": 1}, simulations=1, owner=None,
                            signer=database.log_signer).id


def test_campaign_entries_carry_receipts_and_a_deleted_one_is_named(
        data_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["campaign", "run", f"example:{EXAMPLE}", "-n", "1", "--data-dir",
                 str(data_dir), "--format", "json"]) == 0
    assert main(["campaign", "cancel", _queued(data_dir), "--data-dir", str(data_dir)]) == 0
    _, database = open_database(argparse.Namespace(data_dir=data_dir), log_signer=False)
    with database.session(write=False) as db:
        logged = dict(db.execute(select(Event.kind, LogEntry.index)
                                 .join(LogEntry, LogEntry.event_id == Event.id)
                                 .where(Event.kind.like("campaign.%"))
                                 .order_by(LogEntry.index)).all())
        receipted = set(db.scalars(select(LogReceipt.index)))
    assert set(logged) == {"campaign.created", "campaign.cancelled"}
    assert set(logged.values()) <= receipted

    bundle = _bundle(data_dir)
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert report.ok, report.problems
    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    capsys.readouterr()
    assert main(["audit", "verify", str(path), "--log-key",
                 bundle["log_key"]["public_key"]]) == 0

    created = logged["campaign.created"]
    with database.engine.begin() as connection:
        connection.execute(text("DROP TRIGGER IF EXISTS log_receipts_no_delete"))
        connection.execute(text('DELETE FROM log_receipts WHERE "index" = :i'), {"i": created})
    bundle = _bundle(data_dir)
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert any(p.startswith(f"log entry {created} (campaign.created) carries no receipt")
               for p in report.problems), report.problems
    path.write_text(json.dumps(bundle))
    capsys.readouterr()
    assert main(["audit", "verify", str(path), "--log-key",
                 bundle["log_key"]["public_key"]]) != 0
    assert f"log entry {created} (campaign.created) carries no receipt" in \
        capsys.readouterr().out
