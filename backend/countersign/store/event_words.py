"""Each event's target and change in words, for the activity log.

Both come only from what the log entry records (kind, mission, detail), so the target stored
beside an event row (`events.target`, for filtering) can be recomputed from its log entry and a
row edited behind the app's back is noticed (store/integrity.py)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

MAX_TARGET = 200


def _text(value: Any, limit: int = 80) -> str:
    text = " ".join(str(value).split())
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _short(digest: Any) -> str:
    text = str(digest or "")
    return text[:19] if text.startswith("sha256:") else text[:12]


def _mission_version(mission: str | None, detail: Mapping[str, Any], key: str = "version"
                     ) -> str:
    number = detail.get(key)
    where = f"mission {mission}" if mission else "mission ?"
    return f"{where} v{number}" if number is not None else where


def event_target(kind: str, mission: str | None, detail: Mapping[str, Any]) -> str | None:
    """What the event is about: 'user alice', 'mission survey v2', 'key 1a2b…'."""
    family = kind.split(".", 1)[0]
    target: str | None
    if family == "user":
        target = f"user {detail.get('user')}"
    elif family == "token":
        target = f"token {detail.get('token')}"
    elif family == "key":
        target = f"key {_short(detail.get('key_id'))}"
    elif family == "vehicle":
        target = f"vehicle {detail.get('vehicle')}"
    elif family == "procedure":
        target = f"procedure {detail.get('procedure')} v{detail.get('version')}"
    elif family == "chart":
        charts = detail.get("charts") or []
        target = "chart " + ", ".join(str(c) for c in charts[:5]) + (" …" if len(charts) > 5
                                                                    else "")
    elif kind == "version.created":
        target = _mission_version(mission, detail, "number")
    elif family in {"submission", "approval", "execution", "rehearsal", "campaign"}:
        target = _mission_version(mission, detail)
    elif mission:
        target = f"mission {mission}"
    elif family == "log":
        target = "the log"
    else:
        target = None
    return _text(target, MAX_TARGET) if target is not None else None


def _user_change(kind: str, detail: Mapping[str, Any]) -> str:
    if kind == "user.created":
        return f"created with role {detail.get('role')}"
    if kind == "user.password_changed":
        return "password changed by " + ("themself" if detail.get("by") == "self"
                                         else "an admin")
    parts = []
    if "role" in detail:
        parts.append(f"role from {detail.get('previous_role', '?')} to {detail['role']}")
    if "disabled" in detail:
        parts.append("disabled" if detail["disabled"] else "enabled")
    if "display_name" in detail:
        parts.append(f"display name set to “{_text(detail['display_name'])}”")
    if detail.get("password") == "reset":
        parts.append("password reset by an admin")
    return "; ".join(parts) or "no change"


def _approval_change(kind: str, detail: Mapping[str, Any]) -> str:
    decision = kind.split(".", 1)[1]
    said = f"{_submission(detail)} {decision} with key {_short(detail.get('key_id'))}"
    if detail.get("revokes") is not None:
        said += f", revoking approval {detail['revokes']}"
    reason = detail.get("reason")
    return said + (f": “{_text(reason)}”" if reason else "")


def _rehearsal(detail: Mapping[str, Any]) -> str:
    return f"rehearsal {_text(detail.get('rehearsal'), 10)}"


def _campaign(detail: Mapping[str, Any]) -> str:
    return f"rehearsal campaign {_text(detail.get('campaign'), 16)}"


def _scopes(scopes: Any) -> str:
    # The log records a token's scopes as the token row has them: one space-separated string
    # ("read write"); a list is read too.
    names = scopes.split() if isinstance(scopes, str) else list(scopes or [])
    return ", ".join(map(str, names))


def _draft_burst(detail: Mapping[str, Any]) -> str:
    """One editing burst (store/draft_bursts.py): its revisions and what changed."""
    revision, first = detail.get("revision"), detail.get("from_revision")
    saves = detail.get("saves")
    if first is None or saves is None:  # logged per save before saves were coalesced
        return f"draft saved as revision {revision}"
    changed = [str(c) for c in detail.get("changed") or []]
    more = int(detail.get("more") or 0)
    what = ", ".join(changed[:8]) + (f" and {len(changed) - 8 + more} more" if len(changed) > 8
                                     or more else "")
    span = f"revision {revision}" if first == revision else f"revisions {first}-{revision}"
    return f"draft edited ({saves} saves, {span}){': ' + what if what else ''}"


def _submission(detail: Mapping[str, Any]) -> str:
    return f"submission {detail.get('submission')}"


_CHANGES: dict[str, Callable[[str | None, Mapping[str, Any]], str]] = {
    "mission.created": lambda m, d: "mission created",
    "mission.deleted": lambda m, d: "draft mission deleted",
    "draft.updated": lambda m, d: _draft_burst(d),
    "version.created": lambda m, d: f"version {d.get('number')} created from the draft",
    "submission.created": lambda m, d: f"{_submission(d)} created for review",
    "submission.withdrawn": lambda m, d: f"{_submission(d)} withdrawn",
    "submission.rehearsal_attached": lambda m, d: (
        f"rehearsal record {_short(d.get('record_digest'))} attached to {_submission(d)}"),
    "rehearsal.started": lambda m, d: f"{_rehearsal(d)} started ({d.get('source')})",
    "rehearsal.outcome": lambda m, d: (
        f"{_rehearsal(d)}: goal {d.get('goal')} ended by {d.get('outcome')}"),
    "rehearsal.fault": lambda m, d: f"{_rehearsal(d)}: fault {d.get('fault')} injected",
    "rehearsal.recorded": lambda m, d: (
        f"{_rehearsal(d)} recorded as {_short(d.get('record_digest'))}"),
    "token.created": lambda m, d: (
        f"token “{_text(d.get('name'))}” created ({_scopes(d.get('scopes'))})"),
    "token.revoked": lambda m, d: "token revoked",
    "key.registered": lambda m, d: f"signing key registered for {d.get('user')}",
    "key.revoked": lambda m, d: f"signing key revoked: “{_text(d.get('reason'))}”",
    "vehicle.saved": lambda m, d: f"profile saved as version {d.get('version')}",
    "chart.saved": lambda m, d: f"{len(d.get('charts') or [])} chart(s) saved",
    "chart.deleted": lambda m, d: "chart deleted",
    "execution.recorded": lambda m, d: f"execution recorded: {_text(d.get('summary', ''))}",
    "submission.campaign_attached": lambda m, d: f"{_campaign(d)} attached to {_submission(d)}",
    "campaign.created": lambda m, d: f"{_campaign(d)} queued",
    "campaign.cancelled": lambda m, d: (
        f"{_campaign(d)} cancelled after {d.get('done')} simulations"),
    "log.adopted": lambda m, d: f"{d.get('entries')} earlier log entries adopted",
    "procedure.saved": lambda m, d: f"procedure saved as {_short(d.get('digest'))}",
    "procedure.approved": lambda m, d: _procedure_decision("approved", d),
    "procedure.rejected": lambda m, d: _procedure_decision("rejected", d),
}


def _procedure_decision(decision: str, detail: Mapping[str, Any]) -> str:
    said = f"procedure {decision} with key {_short(detail.get('key_id'))}"
    reason = detail.get("reason")
    return said + (f": “{_text(reason)}”" if reason else "")


def event_change(kind: str, mission: str | None, detail: Mapping[str, Any]) -> str:
    """What changed, in words: 'role from operator to supervisor'."""
    if kind.startswith("user."):
        return _user_change(kind, detail)
    if kind.startswith("approval."):
        return _approval_change(kind, detail)
    words = _CHANGES.get(kind)
    return words(mission, detail) if words else kind
