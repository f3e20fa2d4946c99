"""One statement of the submit rules: store.approvals.submit_refusal is what
the review page shows and what submitting raises (with the codes and submission named)."""

from __future__ import annotations

from typing import Any

from countersign.errors import Conflict, Forbidden
from countersign.store.approvals import submit_refusal
from countersign.store.tables import Submission, User

CLEAN: dict[str, Any] = {"findings": [{"severity": "warning", "code": "NORM"}]}
BROKEN: dict[str, Any] = {"findings": [{"severity": "error", "code": "G3"},
                                       {"severity": "error", "code": "BUDGET"}]}


def _user(role: str) -> User:
    return User(username=role, role=role)


def test_an_operator_may_submit_a_clean_version_nobody_submitted() -> None:
    assert submit_refusal(user=_user("operator"), number=2, report=CLEAN, active=None) is None


def test_only_operators_submit() -> None:
    refused = submit_refusal(user=_user("supervisor"), number=2, report=CLEAN, active=None)
    assert isinstance(refused, Forbidden)
    assert str(refused) == "only operators submit versions"


def test_error_findings_refuse_and_submitting_names_their_codes() -> None:
    shown = submit_refusal(user=_user("operator"), number=2, report=BROKEN, active=None)
    raised = submit_refusal(user=_user("operator"), number=2, report=BROKEN, active=None,
                            detailed=True)
    assert str(shown) == ("version 2 has 2 error finding(s); fix them in the draft and create "
                          "a new version")
    assert isinstance(raised, Conflict)
    assert str(raised) == ("version 2 has 2 error finding(s) (BUDGET, G3); fix them in the draft "
                           "and create a new version")


def test_an_active_submission_refuses_and_ended_ones_do_not() -> None:
    for state in ("submitted", "approved"):
        active = Submission(id=7, state=state)
        shown = submit_refusal(user=_user("operator"), number=3, report=CLEAN, active=active)
        raised = submit_refusal(user=_user("operator"), number=3, report=CLEAN, active=active,
                                detailed=True)
        assert str(shown) == f"version 3 is {state} already"
        assert str(raised) == f"version 3 is {state} already (submission 7)"
    for state in ("withdrawn", "rejected"):
        ended = Submission(id=7, state=state)
        assert submit_refusal(user=_user("operator"), number=3, report=CLEAN,
                              active=ended) is None
