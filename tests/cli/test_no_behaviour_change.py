"""No behaviour change: the CLI's outputs on every built-in example and on the NPS
missions, the signed bytes of the approval fixtures and the committed OpenAPI document are byte
for byte what main printed at aea7afb. tests/cli/behaviour_outputs.py computes them and says
how to regenerate data/no-behaviour-change.json when a change of behaviour is meant."""

from __future__ import annotations

import json

import pytest

from .behaviour_outputs import (
    FIXTURE,
    NPS_MISSIONS,
    NPS_PREFIX,
    cli_runs,
    example_names,
    file_digests,
    run_digest,
    signed_bytes,
)

BEFORE: dict[str, str] = json.loads(FIXTURE.read_text(encoding="utf-8"))
REGENERATE = ("if the change is meant, regenerate the fixture as tests/cli/behaviour_outputs.py "
              "says")


def _differences(keys_and_argv: list[tuple[str, list[str]]]) -> list[str]:
    # An NPS mission's argument reads nps:avcl/NAME.xml, run from NPS_MISSIONS.
    return [f"{key}: countersign {' '.join(argv)}" for key, argv in keys_and_argv
            if BEFORE.get(key) != run_digest(argv)]


def _runs(prefix: str) -> list[tuple[str, list[str]]]:
    return [(key, argv) for key, argv in cli_runs() if key.startswith(prefix)]


@pytest.mark.parametrize("example", example_names())
def test_cli_outputs_on_the_example_unchanged(example: str) -> None:
    runs = _runs(f"example {example} ")
    assert runs
    assert _differences(runs) == [], f"these outputs changed; {REGENERATE}"


def test_cli_outputs_of_the_planner_and_theories_unchanged() -> None:
    assert _differences(_runs("run ")) == [], f"these outputs changed; {REGENERATE}"


def test_cli_outputs_on_the_nps_missions_unchanged() -> None:
    if not NPS_MISSIONS.is_dir():
        pytest.skip(f"the NPS reference missions are absent ({NPS_MISSIONS}): place shared/ "
                    "next to the clone to compare the CLI's outputs on them")
    runs = _runs(NPS_PREFIX)
    assert {key for key, _ in runs} == {key for key in BEFORE if key.startswith(NPS_PREFIX)}
    assert _differences(runs) == [], f"these outputs changed; {REGENERATE}"


@pytest.mark.parametrize("example", example_names())
def test_signed_bytes_of_the_approval_fixtures_unchanged(example: str) -> None:
    prefix = f"approval {example} "
    now = {prefix + key: value for key, value in signed_bytes(example).items()}
    before = {key: value for key, value in BEFORE.items() if key.startswith(prefix)}
    assert before
    assert sorted(k for k in before.keys() | now.keys() if before.get(k) != now.get(k)) == [], (
        f"the bytes a signature covers changed; {REGENERATE}")


def test_openapi_document_and_shared_vectors_unchanged() -> None:
    now = file_digests()
    assert {k: BEFORE.get(k) for k in now} == now, (
        f"a committed document that pins behaviour changed; {REGENERATE}")


def test_every_run_of_the_fixture_is_still_compared() -> None:
    """A run dropped from behaviour_outputs (or an example removed) must not pass silently."""
    compared = {key for key, _ in cli_runs()} | set(file_digests())
    compared |= {f"approval {name} {key}" for name in example_names()
                 for key in signed_bytes(name)}
    expected = set(BEFORE)
    if not NPS_MISSIONS.is_dir():
        expected = {key for key in expected if not key.startswith(NPS_PREFIX)}
    assert compared == expected
