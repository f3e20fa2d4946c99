"""What an API token may do: scopes, and operations that need a signed-in person.

A Bearer token could mint tokens (which then outlived its revocation). Now a token carries
scopes: `read` (GET and HEAD), `write` (other changes) and `decide` (approval decisions and
signing keys, which bind a supervisor), and minting a token needs a browser session."""

from __future__ import annotations

from fastapi import Request

# Operations whose effect is a supervisor's decision or the keys that sign one.
DECIDE_OPERATIONS = frozenset({"prepareDecision", "signDecision", "prepareRevocation",
                               "revokeApproval", "registerKey", "revokeKey"})
# Operations a token may never call: only a person signed in with a password mints tokens.
SESSION_ONLY_OPERATIONS = frozenset({"createToken"})
SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})


def operation_of(request: Request) -> str | None:
    route = request.scope.get("route")
    return getattr(route, "operation_id", None)


def required_scope(request: Request) -> str:
    if operation_of(request) in DECIDE_OPERATIONS:
        return "decide"
    return "read" if request.method in SAFE_METHODS else "write"


def token_refusal(request: Request, scopes: str) -> str | None:
    """Why this token may not make this request, or None."""
    if operation_of(request) in SESSION_ONLY_OPERATIONS:
        return "API tokens cannot create tokens; sign in with a password to create one"
    needed = required_scope(request)
    if needed not in scopes.split():
        return f"this API token lacks the {needed!r} scope (it has: {scopes})"
    return None
