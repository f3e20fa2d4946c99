"""Cheap Argon2 under test: the suite signs in and creates accounts thousands
of times, and each production hash is 64 MiB and tens of milliseconds of CPU. Tests get a
hasher of the same class with argon2-cffi's cheapest parameters, swapped in for the one
process-wide hasher (store/hashing.py's HASHER) wherever a module of ours holds it. Production
code and its settings are untouched: the default parameters are what `countersign serve` and
every subprocess server started by a test use.

Tests that inspect or patch the real hasher (counting the throttle's hashes, checking the stored
parameters) keep it: mark them `production_hashing` (tests/web/test_suite_fixtures.py refuses a
test module that patches HASHER without that marker)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from types import ModuleType

import pytest
from argon2.profiles import CHEAPEST

from countersign.store import accounts, hashing

PRODUCTION_HASHER = hashing.HASHER
# The hash an unknown username is checked against, so that it costs what a wrong password
# does (store/accounts.py): made cheap beside the cheap hasher, to keep that equal.
PRODUCTION_DUMMY = getattr(accounts, "_DUMMY_HASH", None)
MARKER = "production_hashing"


def cheap_hasher() -> hashing.BoundedHasher:
    """The production class (bounded slots, the same process pool) at the cheapest cost; hash and
    salt keep their production lengths so that stored hashes look like real ones."""
    return hashing.BoundedHasher(time_cost=CHEAPEST.time_cost, memory_cost=CHEAPEST.memory_cost,
                                 parallelism=CHEAPEST.parallelism)


def holders(value: object = PRODUCTION_HASHER) -> list[tuple[ModuleType, str]]:
    """Every (module of ours, attribute) that holds `value` (the production hasher)."""
    found = []
    for name, module in list(sys.modules.items()):
        if module is None or not (name == "countersign" or name.startswith("countersign.")):
            continue
        for attribute, held in list(vars(module).items()):
            if held is value:
                found.append((module, attribute))
    return found


@pytest.fixture(autouse=True)
def _cheap_password_hashing(request: pytest.FixtureRequest) -> Iterator[hashing.BoundedHasher]:
    if request.node.get_closest_marker(MARKER) is not None:
        yield PRODUCTION_HASHER
        return
    cheap = cheap_hasher()
    with pytest.MonkeyPatch.context() as patch:
        for module, attribute in holders():
            patch.setattr(module, attribute, cheap)
        if PRODUCTION_DUMMY is not None:
            dummy = cheap.hash("countersign-timing-equaliser")
            for module, attribute in holders(PRODUCTION_DUMMY):
                patch.setattr(module, attribute, dummy)
        yield cheap
