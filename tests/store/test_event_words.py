"""Every event kind the app records reads as a target and a change in words;
a kind added without words would show only its code in the activity log."""

from __future__ import annotations

import re
from pathlib import Path

from countersign.store.event_words import event_change, event_target

BACKEND = Path(__file__).resolve().parents[2] / "backend" / "countersign"


def _recorded_kinds() -> set[str]:
    kinds: set[str] = set()
    for source in BACKEND.rglob("*.py"):
        text = source.read_text()
        if "record(" not in text and "record_event(" not in text:
            continue
        kinds |= set(re.findall(r'kind="([a-z_]+\.[a-z_.]+)"', text))
    kinds |= {f"approval.{d}" for d in ("approved", "rejected", "revoked")}
    kinds.add("log.adopted")
    return kinds


def test_every_recorded_kind_has_words() -> None:
    kinds = _recorded_kinds()
    assert {"user.updated", "submission.created", "vehicle.saved"} <= kinds
    detail = {"user": "alice", "role": "admin", "previous_role": "operator", "number": 2,
              "version": 2, "submission": 7, "rehearsal": "r1", "key_id": "ab" * 32,
              "vehicle": "auv", "charts": ["c1"], "token": 3, "decision": "approved"}
    for kind in sorted(kinds):
        change = event_change(kind, "m", detail)
        assert change and change != kind, kind
        assert event_target(kind, "m", detail), kind


def test_a_role_change_reads_whose_role_from_what_to_what() -> None:
    detail = {"user": "alice", "previous_role": "operator", "role": "supervisor"}
    assert event_target("user.updated", None, detail) == "user alice"
    assert event_change("user.updated", None, detail) == "role from operator to supervisor"
    both = {**detail, "disabled": True}
    assert event_change("user.updated", None, both) == (
        "role from operator to supervisor; disabled")


def test_targets_are_bounded_and_single_line() -> None:
    target = event_target("user.updated", None, {"user": "a\nb" + "x" * 500})
    assert target is not None and len(target) <= 200 and "\n" not in target


def test_token_scopes_read_as_names_as_the_log_records_them() -> None:
    """The token row (and so the log) keeps scopes as one string "read write"; the words
    once spelled it letter by letter ("r, e, a, d")."""
    recorded = {"token": 3, "name": "ci", "scopes": "read write"}
    assert event_change("token.created", None, recorded) == "token “ci” created (read, write)"
    listed = {**recorded, "scopes": ["read"]}
    assert event_change("token.created", None, listed) == "token “ci” created (read)"
