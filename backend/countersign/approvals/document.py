"""The printable approval document of one version.

One function lays it out as titled sections of plain text; the web page prints them (print CSS)
and `text()` joins them for a file. The plain-language orders section is, byte for byte, what
`countersign export --format plain` writes for the same orders (`orders.writers.write`), so the
conditions, terminals and rules the supervisor read are the ones printed."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

from ..orders.model import Orders
from ..orders.team import member_digests, plain_team
from ..orders.writers import write

# A document is for reading: very long finding lists are cut with a note saying how many.
MAX_FINDINGS = 500


@dataclass(frozen=True)
class Section:
    heading: str
    text: str


@dataclass(frozen=True)
class Decision:
    """The version's latest decision, as its approval row and log entry record it."""

    approval: int
    decision: str
    reason: str
    supervisor: str | None
    decided_at: str
    key_id: str
    key_name: str
    log_index: int | None
    revoked_by: int | None = None


def key_fingerprint(key_id: str) -> str:
    """The key id (hex SHA-256 of the raw Ed25519 public key) in groups of four, to read
    aloud; the Keys page shows its first four groups."""
    return " ".join(key_id[i:i + 4] for i in range(0, len(key_id), 4))


def _findings(findings: Sequence[Mapping[str, Any]]) -> str:
    if not findings:
        return "No findings: every check passed."
    errors = sum(1 for f in findings if f.get("severity") == "error")
    lines = [f"{errors} error(s), {len(findings) - errors} warning(s) or note(s)."]
    for finding in findings[:MAX_FINDINGS]:
        subjects = ", ".join(str(s) for s in finding.get("subjects") or [])
        lines.append(f"- {str(finding.get('severity', '')).upper()} {finding.get('code')}"
                     f"{f' [{subjects}]' if subjects else ''}: {finding.get('message')}")
    if len(findings) > MAX_FINDINGS:
        lines.append(f"... and {len(findings) - MAX_FINDINGS} more (see the review page).")
    return "\n".join(lines)


def _paths(orders: Orders, paths: Mapping[str, Any] | None) -> str:
    if not paths:
        return "Paths were not counted (the goal graph is not a DAG)."
    titles = {t.id: t.label for t in orders.terminals or []}
    lines = [f"{paths.get('count')} path(s) from the start to a terminal."]
    for terminal, count in sorted((paths.get("by_terminal") or {}).items()):
        title = titles.get(terminal)
        lines.append(f"- {terminal}{f' ({title})' if title else ''}: {count}")
    return "\n".join(lines)


def _rehearsal(rehearsal: Mapping[str, Any] | None) -> str:
    if rehearsal is None:
        return "None: no rehearsal record is attached to the submission."
    record = rehearsal.get("record") or {}
    energy = record.get("energy") or {}
    runs = record.get("runs") or []
    lines = [
        f"Record {rehearsal.get('digest')}",
        f"Rehearsed orders {rehearsal.get('orders_digest')} "
        f"(version {rehearsal.get('version')}, {rehearsal.get('source')}) by "
        f"{rehearsal.get('owner')} on {_when(str(rehearsal.get('created_at')))}.",
        f"State {record.get('state')}; ended at {record.get('terminal')} "
        f"({record.get('terminal_kind')}) after {len(record.get('goals') or [])} goal(s), "
        f"{record.get('sim_time_s')} s simulated, {len(runs)} run(s), seed {record.get('seed')}.",
    ]
    if energy:
        lines.append(f"Energy used {energy.get('used_wh')} of {energy.get('capacity_wh')} Wh.")
    faults = (record.get("inputs") or {}).get("faults") or []
    lines.append(f"Faults injected: {len(faults)}; replay digest {rehearsal.get('replay_digest')}.")
    return "\n".join(lines)


def _when(iso: str) -> str:
    """'2026-12-02 06:55:44 UTC' from an ISO instant (seconds are enough on paper)."""
    try:
        moment = datetime.fromisoformat(iso).astimezone(UTC)
    except ValueError:
        return iso
    return moment.strftime("%Y-%m-%d %H:%M:%S UTC")


def _decision(decision: Decision | None, pending: str | None) -> tuple[str, str]:
    if decision is None:
        return ("Not decided yet" + (f": {pending}." if pending else "."),
                "No signature: nothing has been signed for this version.")
    said = [f"{decision.decision.capitalize()} (approval {decision.approval}) on "
            f"{_when(decision.decided_at)}.", f"Reason: {decision.reason or '(none given)'}"]
    if decision.revoked_by is not None:
        said.append(f"Revoked since by approval {decision.revoked_by}.")
    signer = [f"Signed by {decision.supervisor} with key “{decision.key_name}”.",
              f"Key fingerprint (SHA-256 of the public key): {key_fingerprint(decision.key_id)}",
              f"Log entry: {decision.log_index if decision.log_index is not None else '?'}"]
    return "\n".join(said), "\n".join(signer)


def approval_document(
    *, mission: str, version: int, digest: str, orders: Orders,
    findings: Sequence[Mapping[str, Any]], paths: Mapping[str, Any] | None,
    rehearsal: Mapping[str, Any] | None, decision: Decision | None, pending: str | None = None,
) -> list[Section]:
    """The document's sections, in reading order."""
    decided, signer = _decision(decision, pending)
    version_text = (f"Mission {mission}, version {version}: “{orders.title}”\n"
                    f"Orders digest (what a signature covers): {digest}")
    plain = write(orders, "plain")
    if orders.team is not None:
        # A team's approval also signs each member's digest (orders/team.py).
        version_text += "".join(f"\nMember {vehicle}: orders digest {member}"
                                for vehicle, member in member_digests(orders).items())
        plain = plain_team(orders)
    return [
        Section("Version", version_text),
        Section("Plain-language orders", plain),
        Section("Findings", _findings(findings)),
        Section("Paths by terminal", _paths(orders, paths)),
        Section("Rehearsal", _rehearsal(rehearsal)),
        Section("Decision", decided),
        Section("Signer", signer),
    ]


def text(sections: Sequence[Section]) -> str:
    """The document as one text file: each heading underlined, sections a blank line apart."""
    return "\n".join(f"{s.heading}\n{'=' * len(s.heading)}\n{s.text.rstrip()}\n"
                     for s in sections)
