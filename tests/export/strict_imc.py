"""A strict IMC reader: pyimclsts' binding generated from LSTS's IMC.xml, plus the checks of
IMC.xml that pyimclsts leaves out.

pyimclsts (LSTS) generates Python classes from IMC.xml; decoding without its fast mode assigns
every field through a descriptor that refuses values under `min`, over `max` or outside a
field's enumeration. It lets a bitfield carry undefined bits and a plaintext field carry
non-ASCII bytes, so `strict_read` checks those from IMC.xml itself (parsed with defusedxml),
and checks min/max/enumerations again so the verdict does not hang on one library's reading.

IMC.xml is LSTS's file: `scripts/fetch-imc-xml` downloads it (at the commit imcpy was built
from) into .cache/imc/, or COUNTERSIGN_IMC_XML names a copy. Without it the tests that need it
skip, unless COUNTERSIGN_REQUIRE_IMC_XML=1 (CI), which makes that a failure."""

from __future__ import annotations

import hashlib
import importlib
import os
import subprocess
import sys
from dataclasses import dataclass, field
from functools import reduce
from operator import or_
from pathlib import Path
from types import ModuleType
from typing import Any, Literal

import imcpy
import pytest
from defusedxml.ElementTree import parse

REPO = Path(__file__).resolve().parents[2]
IMC_XML = Path(os.environ.get("COUNTERSIGN_IMC_XML") or REPO / ".cache" / "imc" / "IMC.xml")


def imc_xml_or_skip() -> Path:
    """IMC.xml as imcpy knows it (same MD5), or skip/fail with what to do about it."""
    reason = (f"IMC.xml not found at {IMC_XML}: run ./scripts/fetch-imc-xml (needs network) "
              "or set COUNTERSIGN_IMC_XML")
    if IMC_XML.is_file():
        # MD5 is how IMC names its own schema version (imcpy.constants.MD5), not a safeguard.
        digest = hashlib.md5(IMC_XML.read_bytes()).hexdigest()
        if digest == imcpy.constants.MD5:
            return IMC_XML
        reason = (f"{IMC_XML} has MD5 {digest}, imcpy was built from {imcpy.constants.MD5} "
                  f"(IMC {imcpy.constants.VERSION}); run ./scripts/fetch-imc-xml")
    if os.environ.get("COUNTERSIGN_REQUIRE_IMC_XML") == "1":
        pytest.fail(reason)
    pytest.skip(reason)


@dataclass
class FieldRule:
    type: str
    minimum: float | None = None
    maximum: float | None = None
    enum: set[int] | None = None
    bits: int | None = None  # the union of the bitfield's defined bits


@dataclass
class Schema:
    messages: dict[str, dict[str, FieldRule]] = field(default_factory=dict)


def _number(text: str) -> int:
    return int(text, 16) if text.lower().startswith("0x") else int(text)


def _ids(element: Any) -> set[int]:
    return {_number(v.get("id")) for v in element.iter("value")}


def _union(bits: set[int]) -> int:
    return reduce(or_, bits, 0)


def load_schema(path: Path) -> Schema:
    root = parse(str(path)).getroot()
    enums = {e.get("abbrev"): _ids(e) for e in root.iterfind("enumerations/def")}
    bitfields = {b.get("abbrev"): _union(_ids(b)) for b in root.iterfind("bitfields/def")}
    schema = Schema()
    for message in root.iter("message"):
        rules: dict[str, FieldRule] = {}
        for f in message.findall("field"):
            rule = FieldRule(f.get("type", ""))
            if f.get("min") is not None:
                rule.minimum = float(f.get("min"))
            if f.get("max") is not None:
                rule.maximum = float(f.get("max"))
            values = _ids(f)
            if f.get("unit") == "Enumerated":
                rule.enum = enums[f.get("enum-def")] if f.get("enum-def") else values
            elif f.get("unit") == "Bitfield":
                rule.bits = bitfields[f.get("bitfield-def")] if f.get("bitfield-def") \
                    else _union(values)
            rules[f.get("abbrev")] = rule
        schema.messages[message.get("abbrev")] = rules
    return schema


def generate_pyimclsts(xml: Path, where: Path) -> ModuleType:
    """pyimclsts' own generator run on `xml`; returns its decoder module (pyimclsts.network),
    which loads the generated `pyimc_generated` package from the working directory."""
    (where / "IMC.xml").write_bytes(xml.read_bytes())
    subprocess.run([sys.executable, "-m", "pyimclsts.extract"], cwd=where, check=True,
                   capture_output=True)
    previous = Path.cwd()
    os.chdir(where)
    try:
        return importlib.import_module("pyimclsts.network")
    finally:
        os.chdir(previous)


class StrictReader:
    def __init__(self, xml: Path, where: Path) -> None:
        self.schema = load_schema(xml)
        self.network = generate_pyimclsts(xml, where)
        self.core = importlib.import_module("pyimclsts.core")

    def read(self, data: bytes) -> dict[str, Any]:
        """The decoded message as plain data (`msg` names each message's type); an
        AssertionError or ValueError names what is out of IMC.xml."""
        order: Literal["big", "little"] = "big" if data[:2] == b"\xfe\x54" else "little"
        assert int.from_bytes(data[:2], order) == 0xFE54, "not an IMC packet (sync)"
        size = int.from_bytes(data[4:6], order)
        assert len(data) == 20 + size + 2, "header size disagrees with the packet"
        assert self.core.CRC16IMB(data[:-2]) == int.from_bytes(data[-2:], order), "CRC"
        message = self.network.unpack(data)  # not fast mode: the descriptors check ranges
        assert type(message).__name__ != "Unknown", "message id unknown to IMC.xml"
        return self._check(message, type(message).__name__)

    def _check(self, message: Any, where: str) -> dict[str, Any]:
        abbrev = message.Attributes.abbrev
        plain: dict[str, Any] = {"msg": abbrev}
        for name, rule in self.schema.messages[abbrev].items():
            # The private slot: pyimclsts' public getter deep-copies, which its messages refuse.
            value = plain[name] = getattr(message, f"_{name}")
            at = f"{where}.{name}"
            if rule.type == "message":
                if value is not None:
                    plain[name] = self._check(value, f"{at}:{value.Attributes.abbrev}")
            elif rule.type == "message-list":
                plain[name] = [self._check(item, f"{at}[{index}]:{item.Attributes.abbrev}")
                               for index, item in enumerate(value)]
            elif rule.type == "plaintext":
                assert all(" " <= c <= "~" or c in "\t\n\r" for c in value), \
                    f"{at} is not printable ASCII: {value!r}"
            elif rule.type != "rawdata":
                number = float(value)
                assert rule.minimum is None or number >= rule.minimum, \
                    f"{at} = {number} under IMC.xml's min {rule.minimum}"
                assert rule.maximum is None or number <= rule.maximum, \
                    f"{at} = {number} over IMC.xml's max {rule.maximum}"
                assert rule.enum is None or int(value) in rule.enum, \
                    f"{at} = {int(value)} is not one of IMC.xml's values {sorted(rule.enum)}"
                assert rule.bits is None or int(value) & ~rule.bits == 0, \
                    f"{at} = {int(value):#x} sets bits IMC.xml does not define ({rule.bits:#x})"
        return plain
