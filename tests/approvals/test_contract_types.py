"""The core contracts as types: the approval statement, the DSSE envelope, the audit bundle and
the validation report each read from JSON and write back exactly the JSON they read
(from_json(to_json(x)) == x and to_json(from_json(d)) == d, key order included, so signed
bytes and digests cannot move), on the fixtures and on generated values; and each refuses a
malformed document with an error naming the field."""

from __future__ import annotations

import json
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.approvals import dsse
from countersign.approvals.bundle import verify_bundle
from countersign.approvals.bundle_model import Bundle
from countersign.approvals.statement import (
    DECISIONS,
    Predicate,
    Statement,
    Subject,
    read_statement,
    statement_bytes,
)
from countersign.orders.examples import example_names, load_example, team_example_names
from countersign.orders.findings import Finding
from countersign.orders.json_fields import Malformed
from countersign.verify.report import validate
from countersign.verify.report_document import PathSummary, ReportDocument
from tests.bench.bench_audit import build_bundle
from tests.cli.behaviour_outputs import approval_statements

EXAMPLE = "search-and-sample"
FAST = settings(max_examples=60, deadline=None,
                suppress_health_check=[HealthCheck.too_slow])

text = st.text(max_size=12)
digest = st.text("0123456789abcdef", min_size=64, max_size=64).map(lambda h: "sha256:" + h)
json_leaf = st.none() | st.booleans() | st.integers(-10**6, 10**6) | text
json_object = st.dictionaries(text, json_leaf, max_size=4)


def _same(data: dict[str, Any], written: dict[str, Any]) -> None:
    """Equal and in the same key order (the prepared statement and the served JSON keep
    their order; signatures and digests are over canonical bytes of equal data)."""
    assert json.dumps(written) == json.dumps(data)


# --- the statement ------------------------------------------------------------------------

@pytest.mark.parametrize("name", [EXAMPLE, *team_example_names()[:1]])
@pytest.mark.parametrize("decision", ["approved", "rejected", "revoked"])
def test_statement_fixtures_round_trip(name: str, decision: str) -> None:
    data = approval_statements(name)[decision]
    statement = Statement.from_json(data)
    _same(data, statement.to_json())
    assert Statement.from_json(statement.to_json()) == statement
    assert read_statement(statement_bytes(data)) == statement


predicates = st.builds(
    Predicate, mission=text, version=st.integers(0, 10**6), submission=st.integers(0, 10**6),
    decision=st.sampled_from(DECISIONS), reason=text, revokes=st.none() | digest,
    report_digest=digest, paths=st.none() | json_object, rehearsal_digest=st.none() | digest,
    vehicle=st.none() | text, author=text, supervisor=text, key_id=text, time=text, nonce=text,
    probabilities=st.none() | json_object,
    exports=st.none() | st.dictionaries(text, digest, max_size=3),
    campaigns=st.none() | st.lists(digest, max_size=3).map(tuple),
    checker=st.none() | text, team=st.none() | st.dictionaries(text, digest, max_size=3))
statements = st.builds(
    Statement, subject=st.tuples(st.builds(Subject, name=text, digest=st.dictionaries(
        st.just("sha256"), text, min_size=1))), predicate=predicates)


@FAST
@given(statements)
def test_generated_statements_round_trip(statement: Statement) -> None:
    assert Statement.from_json(statement.to_json()) == statement
    assert Statement.from_json(json.loads(json.dumps(statement.to_json()))) == statement


REQUIRED_PREDICATE = ("mission", "version", "submission", "decision", "reason", "revokes",
                      "report_digest", "paths", "rehearsal_digest", "vehicle", "author",
                      "supervisor", "key_id", "time", "nonce")


@pytest.mark.parametrize("field", REQUIRED_PREDICATE)
def test_a_statement_without_a_field_is_refused_by_name(field: str) -> None:
    data = approval_statements(EXAMPLE)["approved"]
    del data["predicate"][field]
    with pytest.raises(Malformed, match=rf"statement\.predicate\.{field} is missing"):
        Statement.from_json(data)


@pytest.mark.parametrize(("field", "value", "message"), [
    ("version", "3", r"statement\.predicate\.version must be an integer"),
    ("version", True, r"statement\.predicate\.version must be an integer"),
    ("decision", "maybe", r"statement\.predicate\.decision must be one of"),
    ("campaigns", [1], r"statement\.predicate\.campaigns must be a list of digests"),
    ("exports", {"vehicle/a": 1}, r"statement\.predicate\.exports\.vehicle/a must be a string"),
    ("probabilities", None, r"statement\.predicate\.probabilities must be an object"),
    ("extra", 1, r"statement\.predicate\.extra is not a field"),
])
def test_a_statement_with_a_wrong_field_is_refused_by_name(field: str, value: Any,
                                                           message: str) -> None:
    data = approval_statements(EXAMPLE)["approved"]
    data["predicate"][field] = value
    with pytest.raises(Malformed, match=message):
        Statement.from_json(data)


def test_a_statement_without_a_subject_digest_is_refused_by_name() -> None:
    data = approval_statements(EXAMPLE)["approved"]
    del data["subject"][0]["digest"]
    with pytest.raises(Malformed, match=r"statement\.subject\[0\]\.digest is missing"):
        Statement.from_json(data)


# --- the envelope -------------------------------------------------------------------------

def _envelope() -> dict[str, Any]:
    payload = statement_bytes(approval_statements(EXAMPLE)["approved"])
    return dsse.sign_envelope(payload, dsse.generate_key())


def test_envelope_round_trips() -> None:
    data = _envelope()
    envelope = dsse.Envelope.from_json(data)
    _same(data, envelope.to_json())
    assert dsse.read_envelope(json.dumps(data)) == envelope
    assert dsse.Envelope.from_json(envelope.to_json()) == envelope


b64 = st.binary(max_size=40).map(dsse.b64)
envelopes = st.builds(dsse.Envelope, payloadType=text, payload=b64, signatures=st.tuples(
    st.builds(dsse.Signature, sig=b64, keyid=st.none() | text)))


@FAST
@given(envelopes)
def test_generated_envelopes_round_trip(envelope: dsse.Envelope) -> None:
    assert dsse.Envelope.from_json(envelope.to_json()) == envelope


@pytest.mark.parametrize(("change", "message"), [
    (lambda e: e.pop("payload"), r"envelope\.payload is missing"),
    (lambda e: e.pop("payloadType"), r"envelope\.payloadType is missing"),
    (lambda e: e.update(signatures={}), r"envelope\.signatures must be a list"),
    (lambda e: e["signatures"][0].pop("sig"), r"envelope\.signatures\[0\]\.sig is missing"),
    (lambda e: e["signatures"][0].update(keyid=7),
     r"envelope\.signatures\[0\]\.keyid must be a string"),
    (lambda e: e["signatures"].append(e["signatures"][0]), r"envelope\.signatures has 2"),
])
def test_a_malformed_envelope_is_refused_by_name(change: Any, message: str) -> None:
    data = _envelope()
    change(data)
    with pytest.raises(dsse.SignatureError, match=message):
        dsse.Envelope.from_json(data)


# --- the audit bundle ---------------------------------------------------------------------

@pytest.fixture(scope="module")
def bundle() -> dict[str, Any]:
    data = build_bundle(60, 3)
    assert verify_bundle(data).ok
    return data


def test_bundle_round_trips(bundle: dict[str, Any]) -> None:
    typed = Bundle.from_json(bundle)
    assert Bundle.from_json(typed.to_json()) == typed
    again = Bundle.from_json(json.loads(json.dumps(typed.to_json())))
    assert again == typed
    _same(typed.to_json(), again.to_json())
    assert verify_bundle(typed).to_json() == verify_bundle(bundle).to_json()


@FAST
@given(st.data())
def test_generated_bundles_round_trip(bundle: dict[str, Any], data: st.DataObject) -> None:
    typed = Bundle.from_json(bundle)
    changed = typed.model_copy(update={
        "scope": data.draw(st.none() | text), "signer_refused": data.draw(st.none() | text),
        "entries": data.draw(st.lists(text, max_size=3)),
        "receipts": data.draw(st.lists(st.none() | text, max_size=3)),
        "orders": data.draw(st.dictionaries(digest, json_object, max_size=2)),
    })
    assert Bundle.from_json(changed.to_json()) == changed


@pytest.mark.parametrize(("change", "message"), [
    (lambda b: b["approvals"][0].pop("envelope"), r"approvals\[0\]\.envelope .*Field required"),
    (lambda b: b["approvals"][0].update(log_index="3"), r"approvals\[0\]\.log_index"),
    (lambda b: b.pop("log_key"), r"log_key .*Field required"),
    (lambda b: b["log_key"].pop("public_key"), r"log_key\.public_key .*Field required"),
    (lambda b: b["checkpoints"][0].pop("signature"), r"checkpoints\[0\]\.signature"),
    (lambda b: b.update(entries=[1]), r"entries\[0\]"),
    (lambda b: b.update(format="other"), r"not an audit bundle"),
])
def test_a_malformed_bundle_is_refused_by_name(bundle: dict[str, Any], change: Any,
                                               message: str) -> None:
    data = json.loads(json.dumps(bundle))
    change(data)
    with pytest.raises(Malformed, match=message):
        Bundle.from_json(data)
    # The verifier says so rather than failing: the same words are its one problem.
    report = verify_bundle(data)
    assert len(report.problems) == 1 and Malformed.__name__ not in report.problems[0]


# --- the validation report ----------------------------------------------------------------

@pytest.mark.parametrize("name", example_names())
def test_report_fixtures_round_trip(name: str) -> None:
    data = validate(load_example(name)).to_json()
    document = ReportDocument.from_json(data)
    _same(data, document.to_json())
    assert ReportDocument.from_json(document.to_json()) == document


def test_an_explained_report_round_trips() -> None:
    data = validate(load_example(EXAMPLE)).to_json(explain=True)
    assert "explanation" in data
    _same(data, ReportDocument.from_json(data).to_json())


findings = st.builds(Finding, code=text, severity=st.sampled_from(("error", "warning")),
                     subjects=st.lists(text, max_size=3).map(tuple), message=text,
                     details=json_object)


@st.composite
def reports(draw: st.DrawFn) -> ReportDocument:
    found = tuple(draw(st.lists(findings, max_size=4)))
    explained = draw(st.booleans())
    return ReportDocument(
        mission=draw(text), digest=draw(digest),
        ok=not any(f.severity == "error" for f in found), findings=found,
        paths=draw(st.none() | st.builds(PathSummary, count=st.integers(0, 10**9),
                                         by_terminal=st.dictionaries(text, st.integers(0, 99)))),
        costs=draw(st.none() | json_object), checker=draw(text),
        probabilities=draw(st.none() | json_object), team=draw(st.none() | json_object),
        explanation=draw(st.none() | json_object) if explained else None, explained=explained)


@FAST
@given(reports())
def test_generated_reports_round_trip(report: ReportDocument) -> None:
    again = ReportDocument.from_json(report.to_json())
    assert again == report
    # Finding.details does not take part in equality: compare what is written.
    assert again.to_json() == report.to_json()


@pytest.mark.parametrize(("change", "message"), [
    (lambda r: r.pop("checker"), r"report\.checker is missing"),
    (lambda r: r.pop("paths"), r"report\.paths is missing"),
    (lambda r: r["findings"][0].pop("code"), r"report\.findings\[0\]\.code is missing"),
    (lambda r: r["findings"][0].update(severity="fatal"),
     r"report\.findings\[0\]\.severity must be error or warning"),
    (lambda r: r["paths"].update(count="75"), r"report\.paths\.count must be an integer"),
    (lambda r: r.update(ok=not r["ok"]), r"report\.ok disagrees"),
    (lambda r: r.update(extra=1), r"report\.extra is not a field"),
])
def test_a_malformed_report_is_refused_by_name(change: Any, message: str) -> None:
    data = validate(load_example(EXAMPLE)).to_json()
    data["findings"].append({"code": "TEXT", "severity": "warning", "subjects": ["C1"],
                             "message": "the text says 2 km"})
    ReportDocument.from_json(data)  # as it was, it reads
    change(data)
    with pytest.raises(Malformed, match=message):
        ReportDocument.from_json(data)
