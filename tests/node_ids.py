"""Adapter over pytest's private node id (`Item._id`): the one place the suite touches it.

pytest 9.2 builds a test function's id from its `originalname` and its callspec, so the items
schemathesis makes per API operation (named `test_x[GET /api/...]`, no callspec) all get the
id `test_x`. Under pytest-xdist, which hands out tests by id, 184 fuzz items then ran as two:
the role sweep took 0.5 s instead of minutes. The id is rebuilt from the item's name;
tests/codebase/test_node_ids.py fails when pytest or schemathesis change this."""

from __future__ import annotations

import pytest


def unique_ids(items: list[pytest.Item]) -> None:
    """Give an item whose name carries what its id lacks (a schemathesis operation label) the
    id its name implies; every other item keeps its own."""
    for item in items:
        if getattr(item, "callspec", None) is not None or "[" not in item.name:
            continue
        if item.nodeid.endswith(f"::{item.name}"):
            continue
        parent = item.parent
        assert parent is not None
        item._id = parent._id.child(item.name)  # type: ignore[attr-defined]
