"""Fixtures of the verification tests."""

from __future__ import annotations

import gc
from collections.abc import Iterator

import pytest


@pytest.fixture
def collector_enabled() -> Iterator[None]:
    """The cyclic garbage collector on for the test (a check that pauses it must leave it
    as it found it), and as it was afterwards, whatever the test left it: a test that ends
    with it off left it off for the tests after it in the process (test_cli_startup's)."""
    enabled = gc.isenabled()
    gc.enable()
    yield
    if enabled:
        gc.enable()
    else:
        gc.disable()
