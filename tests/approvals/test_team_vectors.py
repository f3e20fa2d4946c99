"""The member digests of a team approval, checked alike in Python and in the browser.

frontend/src/crypto/__fixtures__/team.json holds the team exemplar's orders as the server
stores them, the approval statement the real builder (approvals/statement.py with
orders/team.member_digests) makes for them, and cases that change the signed member list
(a member missing or added, digests swapped, a vehicle renamed, no list at all). Each case
carries the problems approvals/team_rules.py names; src/crypto/teamRules.test.ts expects the
browser's copy to name the same. Regenerate with
`COUNTERSIGN_UPDATE_VECTORS=1 pytest tests/approvals/test_team_vectors.py`.
"""

from __future__ import annotations

import copy
import json
import os
from pathlib import Path
from typing import Any

from countersign.approvals.statement import build_statement, json_digest, subject_digest
from countersign.approvals.team_rules import member_orders_digests, team_problems
from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import load_example
from countersign.orders.team import member_digests

FIXTURE = (Path(__file__).resolve().parents[2] / "frontend" / "src" / "crypto" / "__fixtures__"
           / "team.json")


def _statement(orders_digest: str, team: dict[str, str] | None) -> dict[str, Any]:
    return build_statement(
        mission="pair", version=1, orders_digest=orders_digest, decision="approved",
        reason="", submission=1, report_digest="sha256:" + "0" * 64, paths=None,
        vehicle=None, author="olga", supervisor="sam", key_id="k", nonce="n",
        time="2026-01-01T00:00:00Z", team=team)


def _cases(signed: dict[str, str]) -> list[dict[str, Any]]:
    """Each case: the orders it is checked against (the team's or one vehicle's) and the
    predicate's `team` (absent when None), with the member each problem must name."""
    first, second = list(signed)[:2]
    missing = {k: v for k, v in signed.items() if k != second}
    extra = {**signed, "auv-9": signed[first]}
    swapped = {**signed, first: signed[second], second: signed[first]}
    renamed = {("auv-9" if k == second else k): v for k, v in signed.items()}
    return [
        {"name": "the builder's statement", "orders": "team", "team": signed, "names": []},
        {"name": "a member missing", "orders": "team", "team": missing, "names": [second]},
        {"name": "an extra member", "orders": "team", "team": extra, "names": ["auv-9"]},
        {"name": "two members' digests swapped", "orders": "team", "team": swapped,
         "names": [first, second]},
        {"name": "a member under another vehicle name", "orders": "team", "team": renamed,
         "names": [second, "auv-9"]},
        {"name": "team orders, no member list signed", "orders": "team", "team": None,
         "names": []},
        {"name": "one vehicle's orders with a member list", "orders": "single",
         "team": signed, "names": []},
        {"name": "a member list that is not vehicle -> digest", "orders": "team",
         "team": {first: 7}, "names": []},
        {"name": "one vehicle's orders, no member list", "orders": "single", "team": None,
         "names": []},
    ]


def vectors() -> dict[str, Any]:
    team_model = load_example("search-and-sample-team")
    team = orders_to_json(team_model)
    single = orders_to_json(load_example("search-and-sample"))
    signed = member_digests(team_model)
    # The JSON the verifiers read hashes as the model the builder signed.
    assert member_orders_digests(team) == signed
    assert json_digest(team) == digest(team_model)
    statement = _statement(digest(team_model), signed)
    assert subject_digest(statement) == json_digest(team)
    cases = []
    for case in _cases(signed):
        predicate = copy.deepcopy(statement["predicate"])
        predicate.pop("team")
        if case["team"] is not None:
            predicate["team"] = case["team"]
        orders = team if case["orders"] == "team" else single
        cases.append({**case, "problems": team_problems(orders, predicate)})
    return {"about": "Team approval vectors, run by tests/approvals/test_team_vectors.py "
                     "(approvals/team_rules.py) and src/crypto/teamRules.test.ts: the orders, "
                     "the builder's statement, and cases of the signed member list with the "
                     "problems both verifiers name.",
            "orders": {"team": team, "single": single}, "statement": statement,
            "cases": cases}


def test_team_vectors_match_the_python_verifier() -> None:
    wanted = json.dumps(vectors(), indent=1, ensure_ascii=False) + "\n"
    if os.environ.get("COUNTERSIGN_UPDATE_VECTORS") == "1":
        FIXTURE.write_text(wanted, encoding="utf-8")
    assert FIXTURE.read_text(encoding="utf-8") == wanted, (
        "frontend/src/crypto/__fixtures__/team.json is out of date: regenerate it with "
        "COUNTERSIGN_UPDATE_VECTORS=1 pytest tests/approvals/test_team_vectors.py")


def test_every_changed_member_list_is_refused_naming_its_members() -> None:
    for case in vectors()["cases"]:
        if case["name"] in ("the builder's statement", "one vehicle's orders, no member list"):
            assert case["problems"] == [], case["name"]
            continue
        assert case["problems"], case["name"]
        for vehicle in case["names"]:
            assert any(f"team member {vehicle}:" in p for p in case["problems"]), (
                case["name"], vehicle)


def test_the_package_verifier_refuses_a_disagreeing_member_list_naming_the_member() -> None:
    from countersign.approved_package.verify import Refusal, check_team

    data = vectors()
    orders = json.dumps(data["orders"]["team"]).encode()
    predicate = data["statement"]["predicate"]
    check_team(orders, predicate)
    check_team(json.dumps(data["orders"]["single"]).encode(), {"team": None})
    for case in data["cases"]:
        if case["problems"] and case["orders"] == "team":
            wrong = {**predicate, "team": case["team"]}
            try:
                check_team(orders, wrong)
            except Refusal as refusal:
                assert refusal.code == "ORDERS"
                assert all(f"team member {v}:" in refusal.message for v in case["names"])
            else:
                raise AssertionError(f"{case['name']}: not refused")


def test_the_standalone_package_verifier_names_the_same_problems() -> None:
    """tools/verify_package.py (one file, no countersign import) checks the member digests
    with its own copy of the rule: on every vector it names exactly the problems
    approvals/team_rules.py names."""
    from ..standalone_tool import standalone_verifier

    tool = standalone_verifier()
    data = vectors()
    assert tool.member_digests(data["orders"]["team"]) == \
        data["statement"]["predicate"]["team"]
    for case in data["cases"]:
        predicate = {**data["statement"]["predicate"], "team": case["team"]}
        if case["team"] is None:
            predicate.pop("team")
        assert tool.team_problems(data["orders"][case["orders"]], predicate) == \
            case["problems"], case["name"]
