"""A package is read in exactly one layout: the canonical tar of the files its manifest lists.

Each hostile tar below was accepted by both verifiers before that rule while GNU tar or
Python's extractall left forged or escaping files on disk. Now both verifiers refuse them,
`vehicle unpack` writes nothing for them, and a good package extracts (with GNU tar, Python
and `vehicle unpack`) to nothing but the signed bytes."""

from __future__ import annotations

import hashlib
import io
import json
import shutil
import subprocess
import sys
import tarfile
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from countersign.approved_package.build import read_tar, write_tar
from countersign.approved_package.verify import verify_package
from countersign.cli import main

from ..standalone_tool import TOOL, standalone_verifier
from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import World

pytestmark = pytest.mark.parametrize("database_url", ["sqlite"], indirect=True)


@pytest.fixture
def approved(world: World) -> Iterator[tuple[bytes, str]]:
    """A good package of an approved version and the log key it verifies under."""
    supervisor = world.client("supervisor")
    number = new_version(world)
    approve(world, supervisor, register_key(supervisor), submit(world, number))
    response = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{number}/package")
    assert response.status_code == 200, response.text
    yield response.content, world.client("auditor").get("/api/log/checkpoint").json()[
        "public_key"]


def _member(name: str, content: bytes = b"", kind: bytes = tarfile.REGTYPE) -> tarfile.TarInfo:
    info = tarfile.TarInfo(name)
    info.size = len(content) if kind == tarfile.REGTYPE else 0
    info.type = kind
    if kind in (tarfile.SYMTYPE, tarfile.LNKTYPE):
        info.linkname = "/etc/passwd"
    return info


def _tar(members: list[tuple[tarfile.TarInfo, bytes]]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w", format=tarfile.GNU_FORMAT) as tar:
        for info, content in members:
            tar.addfile(info, io.BytesIO(content) if info.isfile() else None)
    return out.getvalue()


def _with(good: bytes, extra: list[tuple[tarfile.TarInfo, bytes]], after: str | None = None
          ) -> bytes:
    """The good package's members in order, with `extra` inserted after member `after` (at
    the end when None)."""
    members = [(_member(name, content), content) for name, content in
               sorted(read_tar(good).items())]
    at = len(members) if after is None else \
        next(i for i, (m, _) in enumerate(members) if m.name == after) + 1
    return _tar(members[:at] + extra + members[at:])


def _bad_header_then(good: bytes, name: str, content: bytes) -> bytes:
    """The good tar's members, then a header block with a broken checksum (Python's tarfile
    stops reading there, GNU tar skips it), then a forged member."""
    members = [(_member(n, c), c) for n, c in sorted(read_tar(good).items())]
    body = _tar(members)
    end = len(body)
    while end >= 1024 and body[end - 512:end] == bytes(512):
        end -= 512
    junk = bytearray(b"not a header".ljust(512, b"x"))
    return body[:end] + bytes(junk) + _tar([(_member(name, content), content)])


FORGED = b'{"forged": true}'


def _attacks(good: bytes) -> dict[str, bytes]:
    imc = next(n for n in read_tar(good) if n.endswith(".imc"))
    many = [(_member(f"vehicle/x{i}"), b"") for i in range(100_000)]
    return {
        "./orders.json after orders.json": _with(
            good, [(_member("./orders.json", FORGED), FORGED)], after="orders.json"),
        "./vehicle/<plan>.imc": _with(good, [(_member("./" + imc, FORGED), FORGED)]),
        "a bad header block, then a forged orders.json": _bad_header_then(
            good, "orders.json", FORGED),
        "../../evil.sh": _with(good, [(_member("../../evil.sh", b"echo pwned"), b"echo pwned")]),
        "an absolute member": _with(good, [(_member("/tmp/countersign-evil.sh", b"x"), b"x")]),
        "60 MB of junk after the end": good + b"\x00junk" * (12 * 1024 * 1024),
        "100,000 members": _with(good, many),
        "a symbolic link": _with(good, [(_member("vehicle/link", kind=tarfile.SYMTYPE), b"")]),
        "a hard link": _with(good, [(_member("vehicle/hard", kind=tarfile.LNKTYPE), b"")]),
        "a directory": _with(good, [(_member("vehicle/dir", kind=tarfile.DIRTYPE), b"")]),
        "Orders.json beside orders.json": _with(good, [(_member("Orders.json", FORGED), FORGED)]),
        "an unlisted extra file in canonical form": write_tar(
            {**read_tar(good), "vehicle/extra.txt": b"unsigned"}),
        "the same files in GNU tar's format": _tar(
            [(_member(n, c), c) for n, c in sorted(read_tar(good).items())]),
    }


def _tree(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes()
            for p in sorted(root.rglob("*")) if p.is_file() or p.is_symlink()}


def test_hostile_tars_are_refused_by_both_verifiers_and_unpack_writes_nothing(
        approved: tuple[bytes, str], tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    good, log_key = approved
    standalone = standalone_verifier()
    assert verify_package(good, log_key=log_key).ok
    for attack, data in _attacks(good).items():
        verdict = verify_package(data, log_key=log_key)
        assert (verdict.ok, verdict.code) == (False, "FORMAT"), (attack, verdict)
        ok, code, message = standalone.verify(data, log_key)
        assert (ok, code) == (False, "FORMAT"), (attack, message)
        path = tmp_path / "attack.tar"
        path.write_bytes(data)
        into = tmp_path / "unpacked"
        assert main(["vehicle", "unpack", str(path), "--into", str(into),
                     "--log-key", log_key]) == 1, attack
        assert "REFUSED FORMAT" in capsys.readouterr().out
        assert not into.exists(), attack
        assert standalone.main([str(path), "--log-key", log_key, "--unpack", str(into)]) == 1
        assert not into.exists(), attack


@pytest.mark.skipif(shutil.which("tar") is None, reason="GNU tar is not installed")
def test_a_good_package_extracts_to_the_signed_bytes_and_nothing_else(
        approved: tuple[bytes, str], tmp_path: Path) -> None:
    good, log_key = approved
    signed = read_tar(good)
    manifest = json.loads(signed["manifest.json"])["files"]
    assert {n: "sha256:" + hashlib.sha256(c).hexdigest() for n, c in signed.items()
            if n != "manifest.json"} == manifest
    package = tmp_path / "p.tar"
    package.write_bytes(good)
    def python_extract(into: Path) -> None:
        with tarfile.open(package) as tar:
            tar.extractall(into, filter="data")

    extractors: dict[str, Callable[[Path], None]] = {
        "gnu tar": lambda into: subprocess.run(["tar", "-xf", str(package), "-C", str(into)],
                                               check=True),
        "python": python_extract,
    }
    for how, extract in extractors.items():
        into = tmp_path / how.replace(" ", "-")
        into.mkdir()
        extract(into)
        assert _tree(into) == signed, how
    ours = tmp_path / "ours"
    assert main(["vehicle", "unpack", str(package), "--into", str(ours),
                 "--log-key", log_key]) == 0
    assert _tree(ours) == signed
    tool = tmp_path / "tool"
    result = subprocess.run([sys.executable, str(TOOL), str(package), "--log-key", log_key,
                             "--unpack", str(tool)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert _tree(tool) == signed


def test_unpack_never_writes_into_an_existing_directory(
        approved: tuple[bytes, str], tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    good, log_key = approved
    package = tmp_path / "p.tar"
    package.write_bytes(good)
    existing = tmp_path / "existing"
    existing.mkdir()
    (existing / "orders.json").write_bytes(FORGED)
    assert main(["vehicle", "unpack", str(package), "--into", str(existing),
                 "--log-key", log_key]) == 2
    assert "unpack into a new directory" in capsys.readouterr().err
    assert (existing / "orders.json").read_bytes() == FORGED
    link = tmp_path / "link"
    link.symlink_to(existing)
    assert main(["vehicle", "unpack", str(package), "--into", str(link),
                 "--log-key", log_key]) == 2
    assert standalone_verifier().main([str(package), "--log-key", log_key,
                               "--unpack", str(existing)]) == 2
    assert (existing / "orders.json").read_bytes() == FORGED
