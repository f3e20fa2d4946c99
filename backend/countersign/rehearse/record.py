"""The rehearsal record (issue 8, item 5): what happened, in a canonical JSON form that a
submission attaches and an approval cites by digest, plus the standalone HTML replay.

The JSON holds only what the rehearsal determined (orders digest, options that change the
simulation, seed, inputs given live, outcomes, events, rule firings, energy), never the
rehearsal id, its owner, wall-clock times or the playback speed: the same orders, seed and
inputs give the same digest.
"""

from __future__ import annotations

import copy
import hashlib
from typing import Any, Final

import rfc8785

FORMAT: Final = "countersign.rehearsal/1"


class RehearsalRecord:
    def __init__(self, data: dict[str, Any], html: bytes | None = None) -> None:
        self._data = data
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
