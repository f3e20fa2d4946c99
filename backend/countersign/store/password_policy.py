"""Password strength: length alone let `aaaaaaaaaa`, `password12` or the username
itself through. zxcvbn (Dropbox's estimator, Python port) scores guessability against its
bundled lists of common passwords, names and words, keyboard patterns, repeats and dates;
the username and display name are given to it as words an attacker knows."""

from __future__ import annotations

from typing import Any

MIN_LENGTH = 10
MAX_LENGTH = 1024
# zxcvbn's scale: 3 is "safely unguessable: moderate protection from offline slow-hash
# attacks" (about 10^8 guesses or more); argon2 makes each offline guess slow.
MIN_SCORE = 3


def password_problem(password: str, *, username: str = "",
                     display_name: str = "") -> str | None:
    """Why this password is refused, or None when it is strong enough."""
    if len(password) < MIN_LENGTH:
        return f"a password needs at least {MIN_LENGTH} characters"
    if len(password) > MAX_LENGTH:
        return f"a password may have at most {MAX_LENGTH} characters"
    lowered = password.casefold()
    for known in (username, display_name):
        if known and len(known) >= 3 and known.casefold() in lowered:
            return "a password may not contain the username or display name"
    from zxcvbn import zxcvbn  # type: ignore[import-untyped]

    # zxcvbn's cost grows with length; the first 100 characters decide strength anyway.
    result: dict[str, Any] = zxcvbn(password[:100],
                                    user_inputs=[u for u in (username, display_name) if u])
    if result["score"] < MIN_SCORE:
        feedback = result.get("feedback") or {}
        hint = feedback.get("warning") or "it is easy to guess"
        suggestions = " ".join(feedback.get("suggestions") or [])
        return f"the password is too weak: {hint.rstrip('.')}. {suggestions}".strip()
    return None
