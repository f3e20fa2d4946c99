"""The local pool, the host pool's client and the proxy between them answer the same calls
(web/validations.py): mypy checks their signatures; this checks the names at run time, and
that the proxy forwards every call (multiprocessing's `_exposed_`)."""

from __future__ import annotations

import pytest

from countersign.web.host_pool import HostPoolClient, _PoolProxy
from countersign.web.validation_pool import ValidationPool
from countersign.web.validations import CALLS


def test_the_calls_are_the_protocol_methods() -> None:
    assert set(CALLS) == {"validate", "validate_parts", "running", "pending", "wait_warm"}
    assert tuple(_PoolProxy._exposed_) == CALLS


@pytest.mark.parametrize("implementation", [ValidationPool, HostPoolClient, _PoolProxy])
def test_every_implementation_answers_every_call(implementation: type) -> None:
    missing = [name for name in CALLS if not callable(getattr(implementation, name, None))]
    assert not missing, f"{implementation.__name__} lacks {missing}"


@pytest.mark.parametrize("implementation", [ValidationPool, HostPoolClient])
def test_the_pools_the_app_holds_can_be_shut_down(implementation: type) -> None:
    assert callable(getattr(implementation, "shutdown", None))
