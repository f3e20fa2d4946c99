"""Separation of duties by person, as a log-wide rule, pure: events in,
problems out.

The app refuses a decision by anyone who created the mission, edited its draft or cut a version
up to the one decided, or who submitted it (store/decide_guard.py), whatever their role is now.
A row written behind the app's back skips that guard, so every verifier re-derives it from the
log: `check_log` (log_rules.py) calls `check_duties`; frontend/src/crypto/dutyRules.ts is the
browser's copy, and both run the vectors in frontend/src/crypto/__fixtures__/duties.json."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

# The event kinds that change a mission's content (store/decide_guard.py uses this list too).
EDIT_KINDS = ("mission.created", "draft.updated", "version.created")
DECIDING_KINDS = ("approval.approved", "approval.rejected", "approval.revoked")


def _detail(event: Mapping[str, Any]) -> Mapping[str, Any]:
    detail = event.get("detail")
    return detail if isinstance(detail, Mapping) else {}


def check_duties(events: Sequence[Mapping[str, Any]]) -> list[str]:
    """One problem per decision whose actor authored, edited or cut the mission at or before
    the entry that cut the decided version, or submitted the submission it decides. Without
    that version's cut in the log, every edit before the decision counts (refusing too many
    people is safe, too few is not)."""
    problems: list[str] = []
    edits: dict[Any, list[tuple[int, Any, str]]] = {}  # mission -> (entry, actor, kind)
    cuts: dict[tuple[Any, Any], int] = {}               # (mission, number) -> its cut entry
    submitted: dict[Any, tuple[int, Any, Any, Any]] = {}  # submission -> (entry, actor, m, v)
    for index, event in enumerate(events):
        kind = str(event.get("kind", ""))
        mission, actor, detail = event.get("mission"), event.get("actor"), _detail(event)
        if kind in EDIT_KINDS and mission is not None:
            edits.setdefault(mission, []).append((index, actor, kind))
            if kind == "version.created":
                cuts.setdefault((mission, detail.get("number")), index)
        elif kind == "submission.created":
            submitted.setdefault(detail.get("submission"),
                                 (index, actor, mission, detail.get("version")))
        elif kind in DECIDING_KINDS and actor is not None:
            sub = submitted.get(detail.get("submission"))
            if sub is None:
                continue  # check_log names a decision on a submission the log never created
            sub_index, submitter, target, version = sub
            cut = cuts.get((target, version), index)
            why = [(at, how) for at, who, how in edits.get(target, [])
                   if who == actor and at <= cut]
            if submitter == actor:
                why.append((sub_index, "submission.created"))
            if why:
                at, how = min(why)
                problems.append(
                    f"log entry {index} ({kind}) by {actor} decides submission "
                    f"{detail.get('submission')} of {target} version {version}, but {actor} "
                    f"{'submitted' if how == 'submission.created' else 'edited'} it in log "
                    f"entry {at} ({how}): separation of duties")
    return problems
