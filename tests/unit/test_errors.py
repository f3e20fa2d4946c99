"""Domain errors carry no HTTP (issue 17, item 4): one hierarchy in countersign.errors,
mapped to the status codes the API has always answered by web/problems.py."""

from __future__ import annotations

import pytest

from countersign import errors
from countersign.store.accounts import AccountError, TooManyAttempts
from countersign.store.approvals import BadSignature, LogUnvouched, Refused, Stale
from countersign.store.cosignatures import BadCosignature
from countersign.store.missions import Conflict, MissionError, NotFound, PreconditionFailed
from countersign.store.reauth import PasswordRequired
from countersign.store.rehearsals import NotThisVersion
from countersign.web.problems import status_of
from countersign.web.rehearsal_hub import Busy, TooManyForUser

# The status each error answered with before the hierarchy (their former `status` attributes).
FORMER_STATUS: list[tuple[errors.DomainError, int]] = [
    (MissionError("x"), 400), (NotFound("x"), 404), (Conflict("x"), 409),
    (PreconditionFailed("x", 3), 412), (Refused("x"), 403), (Stale("x"), 409),
    (BadSignature("x"), 400), (LogUnvouched("x"), 503), (PasswordRequired("x"), 403),
    (BadCosignature("x"), 400), (NotThisVersion("x"), 409), (TooManyForUser("x"), 429),
    (Busy("x"), 503), (errors.Gone("x"), 410), (errors.Unprocessable("x"), 422),
    (AccountError("x"), 400), (TooManyAttempts("x"), 429),
]


@pytest.mark.parametrize(("error", "status"), FORMER_STATUS,
                         ids=[type(e).__name__ for e, _ in FORMER_STATUS])
def test_each_domain_error_maps_to_its_former_status(error: errors.DomainError,
                                                     status: int) -> None:
    assert status_of(error) == status


def _subclasses(cls: type) -> set[type]:
    found = set()
    for sub in cls.__subclasses__():
        found |= {sub} | _subclasses(sub)
    return found


def test_no_domain_error_carries_an_http_status() -> None:
    # Importing problems above imported every module that defines one.
    for cls in _subclasses(errors.DomainError) | {errors.DomainError}:
        assert "status" not in vars(cls), f"{cls.__qualname__} carries an HTTP status"
