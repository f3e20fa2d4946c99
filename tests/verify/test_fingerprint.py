"""The checker fingerprint covers exactly the checking code and the ontology."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from countersign.ontology_files import ontology_dir
from countersign.verify import fingerprint
from countersign.verify.report import validate

PACKAGE = Path(fingerprint.__file__).resolve().parents[1]


@pytest.fixture
def copy(tmp_path: Path) -> tuple[Path, Path]:
    """The covered files and one file the fingerprint must ignore, copied to play with."""
    root = tmp_path / "countersign"
    for package in fingerprint.PACKAGES:
        shutil.copytree(PACKAGE / package, root / package,
                        ignore=shutil.ignore_patterns("__pycache__"))
    for name in fingerprint.MODULES:
        shutil.copy(PACKAGE / name, root / name)
    (root / "store").mkdir()
    (root / "store" / "missions.py").write_text("# not a check\n")
    ontology = shutil.copytree(ontology_dir(), tmp_path / "ontology")
    return root, ontology


def test_it_covers_the_checks_and_the_ontology_only() -> None:
    names = [name for name, _ in fingerprint.checked_files()]
    assert names == sorted(names)
    for needed in ("countersign/verify/report.py", "countersign/verify/structure.py",
                   "countersign/orders/canonical.py", "countersign/rules/data/transect.json",
                   "countersign/ontology_files.py", "ontology/meo.ttl", "ontology/shapes.ttl",
                   "ontology/nps-meo3-alignment.ttl"):
        assert needed in names
    assert not [n for n in names if "__pycache__" in n or n.endswith((".pyc", ".pyo"))]
    assert not [n for n in names if n.startswith(("countersign/store/", "countersign/web/"))]


def test_it_is_computed_once_and_carried_by_every_report() -> None:
    value = fingerprint.checker_fingerprint()
    assert re.fullmatch(r"sha256:[0-9a-f]{64}", value)
    assert value == fingerprint.compute_fingerprint()
    assert fingerprint.checker_fingerprint.cache_info().currsize == 1
    from countersign.orders.examples import load_example

    assert validate(load_example("transect-survey")).to_json()["checker"] == value


@pytest.mark.parametrize("change", ["check", "ontology", "new_check_file", "renamed"])
def test_a_change_to_a_check_or_the_ontology_changes_it(copy: tuple[Path, Path],
                                                        change: str) -> None:
    root, ontology = copy
    before = fingerprint.compute_fingerprint(root, ontology)
    check = root / "verify" / "structure.py"
    if change == "check":
        check.write_bytes(check.read_bytes().replace(b"def ", b"def  ", 1))
    elif change == "ontology":
        (ontology / "shapes.ttl").write_bytes((ontology / "shapes.ttl").read_bytes() + b"\n")
    elif change == "new_check_file":
        (root / "rules" / "extra.py").write_text("")
    else:
        check.rename(root / "verify" / "structure2.py")
    assert fingerprint.compute_fingerprint(root, ontology) != before


def test_what_does_not_decide_a_report_leaves_it_alone(copy: tuple[Path, Path]) -> None:
    root, ontology = copy
    before = fingerprint.compute_fingerprint(root, ontology)
    (root / "store" / "missions.py").write_text("# changed\n")
    cache = root / "verify" / "__pycache__"
    cache.mkdir()
    (cache / "report.cpython-311.pyc").write_bytes(b"compiled")
    (ontology / "README.md").write_text("changed\n")
    assert fingerprint.compute_fingerprint(root, ontology) == before
