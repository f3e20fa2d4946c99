"""The log signer: the only holder of the log key, which it keeps in its own directory, outside
the database. It vouches only for what it appended:

* each entry the app appends gets a signed receipt (receipt.py);
* it signs a checkpoint only if every entry since its last signed head carries a valid receipt
  of its own, and the new head is a consistent extension of the last one (an RFC 6962
  consistency proof from the stored head, and the new root recomputed from the stored right
  frontier and the receipted leaves);
* its last signed head lives in a state file beside the key, updated under an exclusive file
  lock, so that several server processes on one host share one history;
* it remembers every committed entry beyond that head (index and leaf hash, in a journal beside
  the state): it refuses to sign or timestamp a head that lacks one of them, and to issue a
  receipt that would put another entry in its place, so an entry deleted from the database
  before a checkpoint covered it is named, not forgotten.

Directory layout (mode 0700): `log-key.pem` (0600; refused if group or others may read it),
`origin` (the log's unique origin line, chosen when the key is made), `state.json`,
`appended` (the journal of committed entries beyond the last signed head), `lock`.

Upgrades: a deployment whose log key predates this directory (a key file in the data directory
or a PEM in the environment) has it imported when the directory's key is first made, so the
log keeps its public key (and its old origin, LEGACY_ORIGIN, under which its old checkpoints
were signed). `fresh` says whether this start made or imported the key: only then may a log
appended before receipts existed be adopted (store/log_adoption.py)."""

from __future__ import annotations

import fcntl
import json
import os
import secrets
import socket
import stat
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from . import dsse
from .log import sign_checkpoint
from .merkle import EMPTY_ROOT, Tree, node_hash, verify_consistency
from .note import Head, cosign, parse_body, verifier_key
from .receipt import make_receipt, verify_receipt

KEY_FILE = "log-key.pem"
ORIGIN_FILE = "origin"
STATE_FILE = "state.json"
APPENDED_FILE = "appended"
LOCK_FILE = "lock"
# The origin line of the checkpoints signed before the signer had its own directory.
LEGACY_ORIGIN = "countersign-log/1"


class SignerError(RuntimeError):
    """The signer will not sign this (unusable key file, or a head it must not vouch for)."""


class SignerRefused(SignerError):
    """A head or an entry the signer must not vouch for (a fork, a roll-back, an entry it did
    not receipt): not the caller's refusal (store.approvals.Refused), the log's."""


def _frontier_append(frontier: list[bytes], size: int, leaf: bytes) -> None:
    """Add a leaf to the right frontier (the roots of the perfect subtrees, left to right)."""
    node = leaf
    while size & 1:
        node = node_hash(frontier.pop(), node)
        size >>= 1
    frontier.append(node)


def _frontier_root(frontier: Sequence[bytes]) -> bytes:
    if not frontier:
        return EMPTY_ROOT
    root = frontier[-1]
    for node in reversed(frontier[:-1]):
        root = node_hash(node, root)
    return root


@dataclass
class _State:
    size: int
    root: bytes
    frontier: list[bytes]
    adopted: int | None = None  # entries adopted at upgrade, appended before receipts


@dataclass(frozen=True)
class LegacyKey:
    """The log key of a deployment from before the signer's directory: its PEM, where it came
    from (for the message), and the file to remove once it is imported (None: environment)."""

    pem: bytes
    source: str
    path: Path | None = None


class LogSigner:
    def __init__(self, directory: Path, legacy: LegacyKey | None = None) -> None:
        self.directory = directory
        # Whether this start made the key (or imported the legacy one): adoption's condition.
        self.fresh = False
        self.imported: str | None = None
        self.key, self.origin = self._load_or_create(legacy)
        self.public: Ed25519PublicKey = self.key.public_key()
        self.public_text = dsse.public_text(self.key)
        self.key_id = dsse.key_id(self.public)
        self.verifier_key = verifier_key(self.origin, dsse.raw_public(self.public))

    # --- key -----------------------------------------------------------------------------

    def _load_or_create(self, legacy: LegacyKey | None) -> tuple[Ed25519PrivateKey, str]:
        self.directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        path = self.directory / KEY_FILE
        if not path.exists():
            # Under the lock: of several processes starting at once, one makes the key.
            with self._locked():
                if not path.exists():
                    return self._create(path, legacy)
        return self._load(path)

    def _create(self, path: Path, legacy: LegacyKey | None) -> tuple[Ed25519PrivateKey, str]:
        if legacy is not None:
            try:
                key = dsse.load_private_pem(legacy.pem)
            except dsse.SignatureError as exc:
                raise SignerError(f"the legacy log key ({legacy.source}): {exc}") from None
            # The log goes on under its old name, so its old checkpoints stay one log with
            # the new ones.
            origin = LEGACY_ORIGIN
        else:
            key = dsse.generate_key()
            # The origin names this log alone: the host and a random instance id.
            origin = f"countersign.{socket.gethostname() or 'host'}/{secrets.token_hex(8)}"
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "wb") as out:
            out.write(dsse.private_pem(key))
            out.flush()
            os.fsync(out.fileno())
        (self.directory / ORIGIN_FILE).write_text(origin + "\n")
        self.fresh = True
        if legacy is not None:
            self.imported = legacy.source
            if legacy.path is not None:
                legacy.path.unlink()  # moved: the key lives in one place, not beside the data
            sys.stderr.write(
                f"countersign: the log key from {legacy.source} was moved to {path} (mode "
                f"0600); the log keeps its public key {dsse.public_text(key)}"
                + (" (COUNTERSIGN_LOG_KEY is no longer read: unset it)"
                   if legacy.path is None else "") + "\n")
        return key, origin

    def _load(self, path: Path) -> tuple[Ed25519PrivateKey, str]:
        origin_path = self.directory / ORIGIN_FILE
        mode = path.stat().st_mode
        if mode & (stat.S_IRWXG | stat.S_IRWXO):
            raise SignerError(f"{path} may be read by others (mode {oct(mode & 0o777)}); "
                              f"chmod 600 {path}")
        try:
            key = dsse.load_private_pem(path.read_bytes())
        except dsse.SignatureError as exc:
            raise SignerError(f"{path}: {exc}") from None
        try:
            origin = origin_path.read_text().strip()
        except OSError:
            raise SignerError(f"{origin_path} is missing: the log's origin line") from None
        if not origin or "\n" in origin:
            raise SignerError(f"{origin_path} does not hold one origin line")
        return key, origin

    # --- receipts ------------------------------------------------------------------------

    def receipt(self, index: int, leaf: str, time: str) -> str:
        """A receipt for the entry about to be appended at `index`; refused when a committed
        entry the signer remembers at that index would be replaced: the log lost an entry
        and must be restored, not written over."""
        with self._locked():
            state = self._read()
            remembered = self._remembered(state.size).get(index)
        if remembered is not None and remembered != leaf:
            raise SignerRefused(
                f"log entry {index} was appended and committed as {remembered[:16]}"
                f"...; the log no longer holds it, and the signer will not append "
                "another entry in its place")
        return make_receipt(self.key, self.origin, index, leaf, time)

    def remember(self, appended: Sequence[tuple[int, str]]) -> None:
        """Record committed entries (index, leaf hash hex): every head the signer signs or
        timestamps from now on must hold them. Called after the appending transaction
        commits, so a rolled-back append is never remembered."""
        if not appended:
            return
        with self._locked():
            size = self._read().size
            lines = "".join(f"{index} {leaf}\n" for index, leaf in appended if index >= size)
            if not lines:
                return
            fd = os.open(self.directory / APPENDED_FILE,
                         os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
            with os.fdopen(fd, "a") as out:
                out.write(lines)
                out.flush()
                os.fsync(out.fileno())

    def _remembered(self, size: int) -> dict[int, str]:
        """The remembered entries at or beyond `size` (the newest record of an index wins)."""
        try:
            text = (self.directory / APPENDED_FILE).read_text()
        except FileNotFoundError:
            return {}
        remembered: dict[int, str] = {}
        for line in text.splitlines():
            index, _, leaf = line.partition(" ")
            if index.isdigit() and int(index) >= size and len(leaf) == 64:
                remembered[int(index)] = leaf
        return remembered

    def _replaced(self, state: _State, size: int, leaf_at: Callable[[int], bytes]) -> str | None:
        """Why a head of `size` (leaves from `leaf_at`) holds another entry where a remembered
        one was committed, or None. Remembered entries beyond `size` are not this head's
        business: they may have been committed after the head's snapshot was read."""
        for index, leaf in sorted(self._remembered(state.size).items()):
            if index < size and leaf_at(index).hex() != leaf:
                return (f"log entry {index} was appended and committed as {leaf[:16]}..., but "
                        f"the log now holds {leaf_at(index).hex()[:16]}... there: an entry was "
                        "replaced")
        return None

    def _compact(self, size: int) -> None:
        """Keep in the journal only what lies beyond the newly signed head."""
        kept = self._remembered(size)
        path = self.directory / APPENDED_FILE
        tmp = path.with_suffix(".tmp")
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "w") as out:
            out.write("".join(f"{index} {leaf}\n" for index, leaf in sorted(kept.items())))
            out.flush()
            os.fsync(out.fileno())
        os.replace(tmp, path)

    def replaced(self, tree: Tree) -> str | None:
        """Why the signer refuses this tree for holding another entry where one it appended
        was committed (None when every remembered entry below its size is in place)."""
        with self._locked():
            return self._replaced(self._read(), tree.size, lambda i: tree.levels[0][i])

    def remembered_beyond(self, size: int) -> dict[int, str]:
        """The committed entries the signer remembers at index `size` or later."""
        with self._locked():
            state = self._read()
            return self._remembered(max(size, state.size))

    # --- checkpoints ---------------------------------------------------------------------

    @contextmanager
    def _locked(self) -> Iterator[None]:
        with open(self.directory / LOCK_FILE, "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)

    def _read(self) -> _State:
        try:
            data = json.loads((self.directory / STATE_FILE).read_text())
        except FileNotFoundError:
            return _State(0, EMPTY_ROOT, [])
        except ValueError:
            raise SignerError(f"{self.directory / STATE_FILE} is not the signer's state") \
                from None
        adopted = data.get("adopted")
        return _State(int(data["size"]), bytes.fromhex(data["root"]),
                      [bytes.fromhex(h) for h in data["frontier"]],
                      int(adopted) if adopted is not None else None)

    def _write(self, state: _State) -> None:
        path = self.directory / STATE_FILE
        tmp = path.with_suffix(".tmp")
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "w") as out:
            data: dict[str, Any] = {"origin": self.origin, "size": state.size,
                                    "root": state.root.hex(),
                                    "frontier": [h.hex() for h in state.frontier]}
            if state.adopted is not None:
                data["adopted"] = state.adopted
            json.dump(data, out)
            out.flush()
            os.fsync(out.fileno())
        os.replace(tmp, path)

    def has_state(self) -> bool:
        return (self.directory / STATE_FILE).exists()

    def adopted(self) -> int | None:
        """How many entries the signer adopted at upgrade (None: it adopted none)."""
        with self._locked():
            return self._read().adopted

    def head(self) -> Head:
        with self._locked():
            state = self._read()
        return Head(self.origin, state.size, state.root)

    def sign_head(self, tree: Tree, receipts: Mapping[int, str],
                  adopted: int | None = None) -> dict[str, Any]:
        """Sign the head of this tree, given the receipts of the entries since the signer's
        last head; refuse (SignerRefused, naming both heads or the entry) a head that is not a
        consistent extension of the last one or covers an entry without a valid receipt.
        The new head becomes the signer's last. `adopted` (the first head only) records in
        the state how many entries were adopted at upgrade."""
        size, root = tree.size, tree.root()
        with self._locked():
            state = self._read()
            last = Head(self.origin, state.size, state.root)
            new = Head(self.origin, size, root)
            if size < state.size:
                raise SignerRefused(
                    f"the log would roll back: the signer's last head is {last}, "
                    f"the new head is {new}")
            if size == state.size:
                if root != state.root:
                    raise SignerRefused(
                        f"the log forks: the signer's last head is {last}, the new "
                        f"head is {new}")
            elif state.size and not verify_consistency(
                    state.size, size, tree.consistency_proof(state.size, size), state.root,
                    root):
                raise SignerRefused(
                    f"the new head is not a consistent extension of the last: the "
                    f"signer's last head is {last}, the new head is {new}")
            replaced = self._replaced(state, size, lambda i: tree.levels[0][i])
            if replaced is not None:
                raise SignerRefused(replaced)
            frontier = list(state.frontier)
            for index in range(state.size, size):
                leaf = tree.levels[0][index]
                try:
                    verify_receipt(receipts.get(index), index=index, leaf=leaf.hex(),
                                   origin=self.origin, key=self.public)
                except dsse.SignatureError as exc:
                    raise SignerRefused(
                        f"log entry {index} {exc}: the signer did not append it and "
                        "will not vouch for it") from None
                _frontier_append(frontier, index, leaf)
            if _frontier_root(frontier) != root:
                raise SignerRefused(
                    f"the receipted entries do not hash to the new head {new} (from "
                    f"the signer's last head {last})")
            signed = sign_checkpoint(self.key, size, root, origin=self.origin)
            if size > state.size:
                if adopted is not None and state.size == 0:
                    state.adopted = adopted
                self._write(_State(size, root, frontier, state.adopted))
                self._compact(size)
        return signed

    # --- timestamps ----------------------------------------------------------------------

    def timestamp_head(self, body: str, when: int) -> str | None:
        """A cosignature line (c2sp.org/tlog-cosignature, by the log key under the log's
        origin) saying that at `when` (Unix seconds) this checkpoint body is the signer's
        latest head, or None when it is not: a package's freshness is this time, not the
        time of the log's last entry, so a quiet log does not expire packages."""
        try:
            head = parse_body(body)
        except dsse.SignatureError:
            return None
        with self._locked():
            state = self._read()
        if (head.origin, head.size, head.root) != (self.origin, state.size, state.root):
            return None
        return cosign(body, self.origin, self.key, when)
