"""Log-wide rules every verifier checks, pure: events in, problems out.

The log is the source of truth. Whatever the tables say, the sequence of logged events must
describe a legal history: one decision per submission, one active submission per version, a
revocation only of an approved submission, no signature by a key after the log revoked it, and
an envelope (in the bundle) for every logged decision, and no decision by its mission's editor
or submitter (duty_rules.py) or by anyone the log did not make a supervisor (role_rules.py).
`countersign audit verify` (approvals/bundle.py) calls `check_log`; the browser has the same
rules in frontend/src/crypto/logRules.ts. `row_problems` compares one table row with its log
entry, for the API's `integrity` lists."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from .duty_rules import check_duties
from .role_rules import check_roles

DECISIONS = ("approval.approved", "approval.rejected")


def _detail(event: Mapping[str, Any]) -> Mapping[str, Any]:
    detail = event.get("detail")
    return detail if isinstance(detail, Mapping) else {}


def check_log(events: Sequence[Mapping[str, Any]], *, enveloped: Iterable[int] | None = None,
              scope: str | None = None) -> list[str]:
    """Problems with the history these log events (in log order) describe. `enveloped` are
    the log indexes whose envelopes the bundle holds (None: do not check); with `scope`, only
    decisions on that mission need one (a bundle exported for one mission)."""
    problems: list[str] = []
    created: dict[int, int] = {}        # submission -> its submission.created entry
    target: dict[int, tuple[Any, Any]] = {}  # submission -> (mission, version)
    state: dict[int, str] = {}          # submission -> submitted/approved/rejected/...
    decided: dict[int, int] = {}        # submission -> its decision entry
    active: dict[tuple[Any, Any], int] = {}  # (mission, version) -> active submission
    revoked_keys: dict[str, int] = {}   # key id -> entry that revoked it
    wanted = set(enveloped) if enveloped is not None else None
    for index, event in enumerate(events):
        kind = str(event.get("kind", ""))
        detail = _detail(event)
        if kind == "key.revoked":
            revoked_keys.setdefault(str(detail.get("key_id")), index)
            continue
        raw = detail.get("submission")
        if not kind.startswith(("submission.", "approval.")) or not isinstance(raw, int):
            continue
        submission = raw
        if kind == "submission.created":
            key = (event.get("mission"), detail.get("version"))
            if submission in created:
                problems.append(f"log entry {index} creates submission {submission} again "
                                f"(first in log entry {created[submission]})")
            if key in active:
                problems.append(
                    f"log entry {index} submits {key[0]} version {key[1]} while submission "
                    f"{active[key]} is still active: one active submission per version")
            created[submission], target[submission] = index, key
            state[submission] = "submitted"
            active.setdefault(key, submission)
            continue
        if submission not in created:
            problems.append(f"log entry {index} ({kind}) concerns submission {submission}, "
                            "which the log never created")
            continue
        now = state[submission]
        if kind in DECISIONS:
            if submission in decided:
                problems.append(f"log entries {decided[submission]} and {index} both decide "
                                f"submission {submission}: one decision per submission")
            elif now != "submitted":
                problems.append(f"log entry {index} decides submission {submission}, which "
                                f"was {now}")
            decided.setdefault(submission, index)
            state[submission] = kind.removeprefix("approval.")
        elif kind == "approval.revoked":
            if now != "approved":
                problems.append(f"log entry {index} revokes submission {submission}, which "
                                f"was {now}, not approved")
            state[submission] = "revoked"
        elif kind == "submission.withdrawn":
            if now != "submitted":
                problems.append(f"log entry {index} withdraws submission {submission}, which "
                                f"was {now}")
            state[submission] = "withdrawn"
        if state[submission] not in ("submitted", "approved") and \
                active.get(target[submission]) == submission:
            del active[target[submission]]
        if kind.startswith("approval."):
            kid = str(detail.get("key_id"))
            if kid in revoked_keys and revoked_keys[kid] < index:
                problems.append(f"log entry {index} is signed with key {kid}, revoked in log "
                                f"entry {revoked_keys[kid]}: a revoked key's later signatures "
                                "are refused")
            if wanted is not None and index not in wanted and \
                    (scope is None or event.get("mission") == scope):
                problems.append(f"log entry {index} records a signed decision ({kind}) but "
                                "the bundle holds no envelope for it (its approvals row was "
                                "removed?)")
    return problems + check_duties(events) + check_roles(events)


def submission_state(events: Iterable[Mapping[str, Any]], submission: int) -> str | None:
    """The state the log gives this submission (None when the log never created it)."""
    state: str | None = None
    for event in events:
        kind = str(event.get("kind", ""))
        if _detail(event).get("submission") != submission:
            continue
        if kind == "submission.created":
            state = "submitted"
        elif state is not None and kind.startswith("approval."):
            state = kind.removeprefix("approval.")
        elif state is not None and kind == "submission.withdrawn":
            state = "withdrawn"
    return state


def row_problems(row: Mapping[str, Any], event: Mapping[str, Any] | None,
                 what: str) -> list[str]:
    """How a table row (field -> value) disagrees with the event its log entry records."""
    if event is None:
        return [f"{what} has no log entry"]
    detail = _detail(event)
    merged = {**detail, "kind": event.get("kind"), "actor": event.get("actor"),
              "mission": event.get("mission")}
    return [f"{what}: the table says {field} = {value!r}, its log entry says "
            f"{merged.get(field)!r}" for field, value in row.items()
            if field in merged and merged.get(field) != value]
