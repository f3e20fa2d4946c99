"""Submission, review, signed decisions, supervisor keys and the transparency log.

Every refusal raises before anything is written, and the route's transaction rolls back, so a
refused request records nothing. Every accepted step is an event (store/events.record), which
appends the next hash-chained leaf of the log in the same transaction.

One module per job (keys, submission, duties, decisions, revocation, log, listing, bundle);
this package re-exports their public names, which is what routes and tests import."""

from __future__ import annotations

from .bundle import build_bundle
from .common import STATEMENT_MAX_AGE, BadDecision, BadKey, BadSignature, Refused, Stale
from .decisions import Context, Prepared, decide, get_approval, prepare_decision
from .duties import ACTIVE_STATES, decision_refusal, previous_approval, submit_refusal
from .keys import key_status, register_key, revoke_key
from .listing import Filters, approval_summaries, approval_summary, approvals_query
from .log import (
    LogUnvouched,
    checkpoint_json,
    checkpoint_refusal,
    consistency_proof,
    entries,
    inclusion_proof,
    latest_checkpoint,
    legacy_signed_note,
    log_index_of,
    log_tree,
    receipt_of,
    vouched_checkpoint,
)
from .revocation import prepare_revocation, revoke
from .submission import get_submission, submit, withdraw

__all__ = [
    "ACTIVE_STATES",
    "STATEMENT_MAX_AGE",
    "BadDecision",
    "BadKey",
    "BadSignature",
    "Context",
    "Filters",
    "LogUnvouched",
    "Prepared",
    "Refused",
    "Stale",
    "approval_summaries",
    "approval_summary",
    "approvals_query",
    "build_bundle",
    "checkpoint_json",
    "checkpoint_refusal",
    "consistency_proof",
    "decide",
    "decision_refusal",
    "entries",
    "get_approval",
    "get_submission",
    "inclusion_proof",
    "key_status",
    "latest_checkpoint",
    "legacy_signed_note",
    "log_index_of",
    "log_tree",
    "prepare_decision",
    "prepare_revocation",
    "previous_approval",
    "receipt_of",
    "register_key",
    "revoke",
    "revoke_key",
    "submit",
    "submit_refusal",
    "vouched_checkpoint",
    "withdraw",
]
