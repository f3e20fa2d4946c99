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
from dataclasses import dataclass, field
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
    history = _History(set(enveloped) if enveloped is not None else None, scope)
    for index, event in enumerate(events):
        history.apply(index, event)
    return history.problems + check_duties(events) + check_roles(events)


@dataclass
class _History:
    """The submissions' states as the log so far describes them, and the problems found."""

    wanted: set[int] | None  # log indexes whose envelopes the bundle holds (None: unchecked)
    scope: str | None
    problems: list[str] = field(default_factory=list)
    created: dict[int, int] = field(default_factory=dict)  # submission -> its created entry
    target: dict[int, tuple[Any, Any]] = field(default_factory=dict)  # -> (mission, version)
    state: dict[int, str] = field(default_factory=dict)  # -> submitted/approved/rejected/...
    decided: dict[int, int] = field(default_factory=dict)  # -> its decision entry
    active: dict[tuple[Any, Any], int] = field(default_factory=dict)  # -> active submission
    revoked_keys: dict[str, int] = field(default_factory=dict)  # key id -> revoking entry

    def apply(self, index: int, event: Mapping[str, Any]) -> None:
        kind = str(event.get("kind", ""))
        detail = _detail(event)
        if kind == "key.revoked":
            self.revoked_keys.setdefault(str(detail.get("key_id")), index)
            return
        submission = detail.get("submission")
        if not kind.startswith(("submission.", "approval.")) or not isinstance(submission, int):
            return
        if kind == "submission.created":
            self._create(index, submission, (event.get("mission"), detail.get("version")))
            return
        if submission not in self.created:
            self.problems.append(f"log entry {index} ({kind}) concerns submission {submission}, "
                                 "which the log never created")
            return
        self._move(index, kind, submission)
        if kind.startswith("approval."):
            self._signed(index, kind, str(detail.get("key_id")), event.get("mission"))

    def _create(self, index: int, submission: int, key: tuple[Any, Any]) -> None:
        if submission in self.created:
            self.problems.append(f"log entry {index} creates submission {submission} again "
                                 f"(first in log entry {self.created[submission]})")
        if key in self.active:
            self.problems.append(
                f"log entry {index} submits {key[0]} version {key[1]} while submission "
                f"{self.active[key]} is still active: one active submission per version")
        self.created[submission], self.target[submission] = index, key
        self.state[submission] = "submitted"
        self.active.setdefault(key, submission)

    def _move(self, index: int, kind: str, submission: int) -> None:
        """A decision, revocation or withdrawal, from the state the submission was in."""
        now = self.state[submission]
        if kind in DECISIONS:
            if submission in self.decided:
                self.problems.append(f"log entries {self.decided[submission]} and {index} both "
                                     f"decide submission {submission}: one decision per "
                                     "submission")
            elif now != "submitted":
                self.problems.append(f"log entry {index} decides submission {submission}, "
                                     f"which was {now}")
            self.decided.setdefault(submission, index)
            self.state[submission] = kind.removeprefix("approval.")
        elif kind == "approval.revoked":
            if now != "approved":
                self.problems.append(f"log entry {index} revokes submission {submission}, "
                                     f"which was {now}, not approved")
            self.state[submission] = "revoked"
        elif kind == "submission.withdrawn":
            if now != "submitted":
                self.problems.append(f"log entry {index} withdraws submission {submission}, "
                                     f"which was {now}")
            self.state[submission] = "withdrawn"
        if self.state[submission] not in ("submitted", "approved") and \
                self.active.get(self.target[submission]) == submission:
            del self.active[self.target[submission]]

    def _signed(self, index: int, kind: str, kid: str, mission: Any) -> None:
        """A signed decision: by a key not revoked before it, with its envelope at hand."""
        if kid in self.revoked_keys and self.revoked_keys[kid] < index:
            self.problems.append(f"log entry {index} is signed with key {kid}, revoked in log "
                                 f"entry {self.revoked_keys[kid]}: a revoked key's later "
                                 "signatures are refused")
        if self.wanted is not None and index not in self.wanted and \
                (self.scope is None or mission == self.scope):
            self.problems.append(f"log entry {index} records a signed decision ({kind}) but "
                                 "the bundle holds no envelope for it (its approvals row was "
                                 "removed?)")


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
