"""The per-account password-check limit a deployment may set (settings.py, read by
store/login_throttle.py when it is imported)."""

from __future__ import annotations

import pytest

from countersign.settings import SettingsError, password_checks_per_minute

VARIABLE = "COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE"


def test_the_limit_is_ten_unless_set_and_a_bad_value_is_named(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(VARIABLE, raising=False)
    assert password_checks_per_minute() == 10
    for text, limit in ((" ", 10), ("", 10), ("600", 600), (" 7 ", 7)):
        monkeypatch.setenv(VARIABLE, text)
        assert password_checks_per_minute() == limit
    for bad in ("0", "-3", "1001", "ten", "1e3"):
        monkeypatch.setenv(VARIABLE, bad)
        with pytest.raises(SettingsError) as refused:
            password_checks_per_minute()
        assert str(refused.value) == (f"{VARIABLE} must be a whole number from 1 to 1000, "
                                      f"not {bad!r}")
