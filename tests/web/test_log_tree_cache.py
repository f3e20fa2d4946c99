"""The log's Merkle tree is cached by its Database object, not in a
module-level table keyed by engine URL that every Database of one URL shared."""

from __future__ import annotations

from countersign.store import approvals as service
from countersign.store.db import Database

from .conftest import World


def test_the_log_tree_is_cached_by_the_database_that_read_it(world: World) -> None:
    database = world.database
    database.log_tree_cache.clear()
    with database.session(write=False) as db:
        tree = service.log_tree(db)
    assert tree.size > 0
    assert database.log_tree_cache.tree is tree
    other = Database(database.url)
    try:
        assert other.log_tree_cache.tree is None
        with other.session(write=False) as db:
            assert service.log_tree(db).root() == tree.root()
        assert other.log_tree_cache.tree is not tree
    finally:
        other.engine.dispose()
