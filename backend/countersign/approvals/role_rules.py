"""Who may decide, from the log, pure: events in, roles and problems out.

A database writer can `UPDATE users SET role = 'supervisor'`; the users table is not evidence.
Every account's creation (`user.created`, with its role), role change and disabling
(`user.updated`) and password reset is a log entry with the log signer's receipt, so the log
tells each person's role at every point of its history. A decision (approval, rejection,
revocation) counts only from someone the log shows as an enabled supervisor at that entry, and
a change to an account counts only when made by someone the log shows as an admin (or by no one:
`countersign users create` and the demo seed run as the system, beside the log key).

`check_log` (log_rules.py) calls `check_roles`; the decision guard (store/decide_guard.py)
replays the same `RoleBook` over the account entries; frontend/src/crypto/roleRules.ts is the
browser's copy, and both run the vectors in frontend/src/crypto/__fixtures__/roles.json."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from .duty_rules import DECIDING_KINDS

ACCOUNT_KINDS = ("user.created", "user.updated", "user.password_changed")
DECIDER = "supervisor"
GRANTER = "admin"


@dataclass(frozen=True)
class LoggedRole:
    """A person's role as the log gives it, the entry that gave it, and the entry that
    disabled the account (None while enabled)."""

    role: str
    at: int
    disabled_at: int | None = None


def _detail(event: Mapping[str, Any]) -> Mapping[str, Any]:
    detail = event.get("detail")
    return detail if isinstance(detail, Mapping) else {}


@dataclass
class RoleBook:
    """The roles the log has given so far; `apply` each entry in log order."""

    roles: dict[str, LoggedRole] = field(default_factory=dict)
    # Accounts whose only creation entry was made by someone who was not an admin.
    ungranted: dict[str, int] = field(default_factory=dict)

    def decision_problem(self, user: str) -> str | None:
        """Why the log does not let `user` decide now (None when it does)."""
        logged = self.roles.get(user)
        if logged is None and user in self.ungranted:
            return (f"the log gave {user} no role (log entry {self.ungranted[user]} was not "
                    "made by an admin)")
        if logged is None:
            return f"the log never created {user} or gave them a role"
        if logged.role != DECIDER:
            return f"the log made {user} {logged.role} in log entry {logged.at}"
        if logged.disabled_at is not None:
            return f"the log disabled {user} in log entry {logged.disabled_at}"
        return None

    def _grant_problem(self, actor: Any) -> str | None:
        if actor is None:
            return None  # the system: `countersign users create`, the demo seed
        logged = self.roles.get(str(actor))
        if logged is None:
            return f"the log never created {actor} or gave them a role"
        if logged.role != GRANTER or logged.disabled_at is not None:
            return (f"the log made {actor} {logged.role} in log entry {logged.at}"
                    if logged.role != GRANTER else
                    f"the log disabled {actor} in log entry {logged.disabled_at}")
        return None

    def apply(self, index: int, event: Mapping[str, Any]) -> str | None:
        """Take one log entry into account; the problem it shows, if any. An account change
        by someone who was not an admin changes nothing here."""
        kind, actor, detail = str(event.get("kind", "")), event.get("actor"), _detail(event)
        if kind in DECIDING_KINDS and actor is not None:
            why = self.decision_problem(str(actor))
            return None if why is None else (
                f"log entry {index} ({kind}) by {actor}, but {why}: only an enabled "
                "supervisor decides")
        if kind not in ACCOUNT_KINDS or not isinstance(detail.get("user"), str):
            return None
        user = str(detail["user"])
        if kind == "user.password_changed" and detail.get("by") == "self" and actor == user:
            return None  # one's own password: no power granted
        why = self._grant_problem(actor)
        if why is not None:
            self.ungranted.setdefault(user, index)
            return (f"log entry {index} ({kind}) by {actor} changes the account of {user}, but "
                    f"{why}: only an admin changes accounts, so it gives no role")
        before = self.roles.get(user)
        role = detail.get("role")
        if kind == "user.created" or (isinstance(role, str) and before is None):
            self.roles[user] = LoggedRole(str(role), index)
        elif before is not None:
            if isinstance(role, str) and role != before.role:
                before = LoggedRole(role, index, before.disabled_at)
            disabled = detail.get("disabled")
            if disabled is True and before.disabled_at is None:
                before = LoggedRole(before.role, before.at, index)
            elif disabled is False:
                before = LoggedRole(before.role, before.at, None)
            self.roles[user] = before
        return None


def check_roles(events: Sequence[Mapping[str, Any]]) -> list[str]:
    """One problem per decision by someone the log did not make an enabled supervisor, and
    per account change by someone it did not make an admin."""
    book = RoleBook()
    found = (book.apply(index, event) for index, event in enumerate(events))
    return [problem for problem in found if problem is not None]


def replay(entries: Iterable[tuple[int, Mapping[str, Any]]]) -> RoleBook:
    """The roles after these (index, event) pairs, in log order (the account entries alone
    suffice: decisions change no role)."""
    book = RoleBook()
    for index, event in entries:
        book.apply(index, event)
    return book
