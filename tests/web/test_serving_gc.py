"""A serving app collects young garbage after tens of thousands of allocations, not Python's
700 (a one-goal edit of a 1,000-goal mission ran 76 collections, 40 ms of its CPU), and gives
the process its thresholds back when it stops."""

from __future__ import annotations

import gc
from pathlib import Path

from fastapi.testclient import TestClient

from countersign.settings import Settings
from countersign.store.db import Database
from countersign.web.app import YOUNG_GC_THRESHOLD, create_app


def test_the_young_threshold_is_raised_while_the_app_serves(tmp_path: Path) -> None:
    before = gc.get_threshold()
    url = f"sqlite:///{tmp_path / 'gc.db'}"
    database = Database(url)
    app = create_app(Settings(data_dir=tmp_path, database_url=url, validation_processes=0),
                     database)
    try:
        with TestClient(app) as client:
            assert client.get("/api/health").status_code == 200
            serving = gc.get_threshold()
            assert serving[0] >= YOUNG_GC_THRESHOLD and serving[1:] == before[1:]
        assert gc.get_threshold() == before
    finally:
        gc.set_threshold(*before)
        database.engine.dispose()
