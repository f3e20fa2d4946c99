"""The rehearsal record: what happened, in a canonical JSON form that a
submission attaches and an approval cites by digest, plus the standalone HTML replay.

The JSON holds only what the rehearsal determined (orders digest, options that change the
simulation, seed, inputs given live, outcomes, events, rule firings, energy), never the
rehearsal id, its owner, wall-clock times or the playback speed: the same orders, seed and
inputs give the same digest.
"""

from __future__ import annotations

import copy
import hashlib
import math
from typing import Any, Final

import rfc8785

FORMAT: Final = "countersign.rehearsal/1"


# RFC 8785 (I-JSON) holds finite doubles and integers within +-(2^53 - 1) only.
MAX_SAFE_INTEGER: Final = 2**53 - 1
MAX_NAMED: Final = 100


def representable(data: dict[str, Any]) -> dict[str, Any]:
    """`data` with every number RFC 8785 cannot hold (an infinite or NaN float, an integer
    beyond 2^53) replaced by null and its JSON path listed under `unrepresentable`: stopping a
    rehearsal whose clock or energy overflowed (speed 1e308) stores a record that says
    so, instead of failing to compute its digest and losing it. Records with no such number are
    unchanged, and so are their digests."""
    named: list[str] = []

    def clean(value: Any, path: str) -> Any:
        if isinstance(value, bool) or value is None or isinstance(value, str):
            return value
        if (isinstance(value, float) and not math.isfinite(value)) or (
                isinstance(value, int) and abs(value) > MAX_SAFE_INTEGER):
            named.append(path)
            return None
        if isinstance(value, dict):
            return {k: clean(v, f"{path}.{k}") for k, v in value.items()}
        if isinstance(value, list | tuple):
            return [clean(v, f"{path}[{i}]") for i, v in enumerate(value)]
        return value

    cleaned: dict[str, Any] = clean(data, "$")
    if named:
        cleaned["unrepresentable"] = named[:MAX_NAMED]
    return cleaned


class RehearsalRecord:
    def __init__(self, data: dict[str, Any], html: bytes | None = None) -> None:
        self._data = representable(data)
        self._html = html
        self._digest: str | None = None

    def to_json(self) -> dict[str, Any]:
        return copy.deepcopy(self._data)

    def canonical_bytes(self) -> bytes:
        return bytes(rfc8785.dumps(self._data))

    @property
    def digest(self) -> str:
        if self._digest is None:
            self._digest = "sha256:" + hashlib.sha256(self.canonical_bytes()).hexdigest()
        return self._digest

    @property
    def has_replay(self) -> bool:
        return self._html is not None

    def replay_html(self) -> bytes:
        """A self-contained HTML page (viser's client with the recorded scene embedded) that
        plays the rehearsal back offline."""
        if self._html is None:
            raise LookupError(
                "this record has no scene recording: it was taken before the rehearsal "
                "finished, or the rehearsal ran without a scene (headless)"
            )
        return self._html

    @property
    def outcomes(self) -> list[str]:
        return list(self._data.get("outcomes", []))

    def __repr__(self) -> str:
        return f"RehearsalRecord({self.digest})"
