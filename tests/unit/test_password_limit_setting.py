"""The per-account password-check limit a deployment may set (store/login_throttle.py)."""

from __future__ import annotations

import pytest

from countersign.store import login_throttle


def test_the_limit_is_ten_unless_set_and_a_bad_value_is_named() -> None:
    assert login_throttle.account_hashes_per_minute(None) == 10
    assert login_throttle.account_hashes_per_minute(" ") == 10
    assert login_throttle.account_hashes_per_minute("600") == 600
    for bad in ("0", "-3", "1001", "ten", "1e3"):
        with pytest.raises(ValueError, match="COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE"):
            login_throttle.account_hashes_per_minute(bad)
