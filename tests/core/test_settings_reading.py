"""settings.py reads its groups with pydantic alone; pydantic-settings, which it used before and
which the command line no longer imports for its start-up cost, is the oracle here: for any
environment, each group reads the same values, or is refused with the same message."""

from __future__ import annotations

import os
from typing import Any
from unittest import mock

from hypothesis import HealthCheck, example, given
from hypothesis import settings as hypothesis_settings
from hypothesis import strategies as st
from pydantic import ValidationError
from pydantic_settings import BaseSettings, SettingsConfigDict

from countersign import settings

from .test_settings_place import GROUPS, VARIABLES


def _oracle(group: type[settings._Environment]) -> type[BaseSettings]:
    """The group as a pydantic-settings class, configured as settings.py configured it."""

    class Oracle(BaseSettings, group):  # type: ignore[misc, valid-type]
        model_config = SettingsConfigDict(case_sensitive=True, frozen=True, extra="ignore")

    return Oracle


ORACLES = {group: _oracle(group) for group in GROUPS}
VALUES = st.one_of(
    st.sampled_from(["", " ", "0", "2", " 7 ", "64", "65", "-1", "1.5", "yes", "True", "no",
                     "1", "/tmp/x", "~/cache", "[1, 2]", '{"a": 1}', "null", "none",
                     "https://tiles.example/{z}/{x}/{y}.png", "http://h/{z}", "cst_token"]),
    st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"),
            max_size=20))
NAMES = st.sampled_from(sorted(VARIABLES | {name.lower() for name in VARIABLES}
                               | {"COUNTERSIGN_OTHER", "server", "debug"}))


def _outcome(read: Any) -> tuple[str, Any]:
    try:
        return "ok", read().model_dump()
    except settings.SettingsError as exc:
        return "refused", str(exc)


def _oracle_outcome(group: type[settings._Environment]) -> tuple[str, Any]:
    try:
        return "ok", ORACLES[group]().model_dump()
    except ValidationError as exc:
        return "refused", "; ".join(settings._explain(error) for error in exc.errors())


@hypothesis_settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])  # busy machine
@given(st.dictionaries(NAMES, VALUES, max_size=8))
@example({})
@example({"COUNTERSIGN_VALIDATION_PROCESSES": "65", "COUNTERSIGN_DEBUG": ""})
@example({"COUNTERSIGN_TOKEN": " ", "COUNTERSIGN_LAND_MASK_CACHE": "/tmp/mask.npz",
          "COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE": " "})
@example({"COUNTERSIGN_MAP_TILES": "ftp://x/{z}", "COUNTERSIGN_SECURE_COOKIES": "YES"})
def test_each_group_reads_as_pydantic_settings_read_it(environment: dict[str, str]) -> None:
    with mock.patch.dict(os.environ, environment, clear=True):
        for group in GROUPS:
            assert _outcome(lambda g=group: settings.read(g)) == _oracle_outcome(group), group


def test_the_oracle_sees_a_difference() -> None:
    # The comparison is not vacuous: a variable read under another name differs.
    with mock.patch.dict(os.environ, {"COUNTERSIGN_SERVER": "http://elsewhere:1"}, clear=True):
        assert _oracle_outcome(settings.ClientEnvironment)[1]["server"] == "http://elsewhere:1"
        assert _outcome(lambda: settings.read(settings.ClientEnvironment)) == \
            _oracle_outcome(settings.ClientEnvironment)
