"""Starting on a database already at head costs no Alembic run: the app starts once per API test
and once per server process, and loading every migration script was most of that start."""

from __future__ import annotations

from pathlib import Path

import pytest
from alembic import command
from sqlalchemy import text

from countersign.store import db as store_db
from countersign.store.db import Database, alembic_config


def _refuse_upgrade(*args: object, **kwargs: object) -> None:
    raise AssertionError("Alembic's upgrade ran on a database at head")


def test_a_database_at_head_is_not_upgraded_again(tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    database = Database(f"sqlite:///{tmp_path / 'db.sqlite'}")
    database.migrate()
    monkeypatch.setattr(command, "upgrade", _refuse_upgrade)
    database.migrate()
    database.engine.dispose()


def test_a_database_below_head_is_still_upgraded(tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'db.sqlite'}"
    database = Database(url)
    database.migrate()
    (head,) = store_db._revisions()[1]
    with database.engine.begin() as connection:
        config = alembic_config(url)
        config.attributes["connection"] = connection
        command.downgrade(config, "-1")
    database.migrate()
    with database.engine.connect() as connection:
        assert connection.execute(text("SELECT version_num FROM alembic_version")).scalar_one() \
            == head
    database.engine.dispose()
