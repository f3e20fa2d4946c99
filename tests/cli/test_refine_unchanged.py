"""Orders without `refines` print exactly what they printed before refinement existed:
every CLI output of every earlier built-in example is compared with digests captured from
the commit before refinement (tests/cli/cli_outputs.py says how)."""

from __future__ import annotations

import json

import pytest

from countersign.orders.canonical import digest
from countersign.orders.examples import load_example

from .cli_outputs import COMMANDS, EXAMPLES, FIXTURE, output_digest

BEFORE: dict[str, str] = json.loads(FIXTURE.read_text())
# Digests of the earlier examples before refinement existed.
DIGESTS = {
    "search-and-sample":
        "sha256:5ad77442b175e850d631e7296abf7fddb48e9f00923e17c776e13095c2752748",
}


@pytest.mark.parametrize("example", EXAMPLES)
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_output_unchanged(example: str, command: str) -> None:
    assert output_digest(command, example) == BEFORE[f"{example} {command}"]


def test_digest_unchanged() -> None:
    for name, expected in DIGESTS.items():
        assert digest(load_example(name)) == expected
