from __future__ import annotations

from collections.abc import Iterator

import pytest

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.rehearse.manager import RehearsalManager


@pytest.fixture
def exemplar() -> Orders:
    return load_example("search-and-sample")


@pytest.fixture
def manager() -> Iterator[RehearsalManager]:
    manager = RehearsalManager(max_active=16, idle_timeout_s=600.0)
    try:
        yield manager
    finally:
        manager.shutdown()
