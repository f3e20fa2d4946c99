"""The hash an unknown username is checked against is written in the code (store/accounts.py)
rather than made at import: it must stay a hash with the production hasher's parameters, or an
unknown username would cost less than a wrong password and show itself by its speed."""

from __future__ import annotations

import pytest
from argon2 import PasswordHasher, Type, extract_parameters
from argon2.exceptions import VerifyMismatchError

from ..cheap_hashing import PRODUCTION_DUMMY, PRODUCTION_HASHER


def test_the_dummy_hash_costs_what_a_real_one_does() -> None:
    assert PRODUCTION_DUMMY is not None
    assert extract_parameters(PRODUCTION_DUMMY).type is Type.ID
    assert not PRODUCTION_HASHER.check_needs_rehash(PRODUCTION_DUMMY)
    with pytest.raises(VerifyMismatchError):  # a well-formed hash that nothing matches
        PasswordHasher().verify(PRODUCTION_DUMMY, "countersign-timing-equaliser")
