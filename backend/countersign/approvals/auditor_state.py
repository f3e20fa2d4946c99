"""What an auditor (`audit verify --state`, `countersign witness`) remembers between runs: the
last verified tree head of each log, by origin, so that the next checkpoint must be a
consistent extension of it (no rollback, no fork)."""

from __future__ import annotations

import json
import os
from pathlib import Path

from .dsse import SignatureError
from .note import Head

STATE_FORMAT = "countersign.auditor-state/1"


def load_state(path: Path) -> dict[str, Head]:
    """The heads by origin; {} when the file does not exist yet (first use)."""
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        return {}
    except ValueError:
        raise SignatureError(f"{path} is not an auditor state file") from None
    if not isinstance(data, dict) or data.get("format") != STATE_FORMAT:
        raise SignatureError(f"{path} is not an auditor state file ({STATE_FORMAT})")
    try:
        return {origin: Head(origin, int(h["size"]), bytes.fromhex(h["root"]))
                for origin, h in data["logs"].items()}
    except (KeyError, TypeError, ValueError, AttributeError):
        raise SignatureError(f"{path} holds a malformed tree head") from None


def save_state(path: Path, heads: dict[str, Head]) -> None:
    tmp = path.with_name(path.name + ".tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w") as out:
        json.dump({"format": STATE_FORMAT, "logs": {
            o: {"size": h.size, "root": h.root.hex()} for o, h in sorted(heads.items())}},
            out, indent=1)
    os.replace(tmp, path)


def consistency_problem(seen: Head, new: Head, proof_ok: bool | None) -> str | None:
    """Why `new` does not continue the history `seen` (None when it does); `proof_ok` is the
    result of checking the consistency proof from seen.size to new.size (when sizes differ)."""
    if new.size < seen.size:
        return (f"the log was rolled back (truncated): a checkpoint seen before has {seen}; "
                f"the server now presents {new}")
    if new.size == seen.size and new.root != seen.root:
        return f"the log forks: a checkpoint seen before has {seen}; the server now presents {new}"
    if new.size > seen.size and seen.size and not proof_ok:
        return (f"the log forks from the checkpoint seen before ({seen}): no valid consistency "
                f"proof to {new}")
    return None
