"""The one JSON policy: non-finite numbers, duplicate keys and deep nesting are
refused with their JSON path, by the library and by the command line (exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from countersign import strict_json
from countersign.orders.canonical import orders_to_json
from countersign.orders.examples import load_example

from ..cli.test_bad_input import run_cli, write


@pytest.mark.parametrize("number", ["1e999", "-1e999", "Infinity", "-Infinity", "NaN"])
def test_non_finite_number_names_its_path(number: str) -> None:
    with pytest.raises(strict_json.JsonPolicyError) as caught:
        strict_json.loads(f'{{"a": [1, {{"b c": {number}}}]}}')
    assert caught.value.path == '$.a[1]["b c"]'


def test_duplicate_keys_and_depth_are_refused() -> None:
    with pytest.raises(strict_json.JsonPolicyError, match="twice"):
        strict_json.loads('{"a": 1, "a": 2}')
    with pytest.raises(strict_json.JsonPolicyError, match="deeper"):
        strict_json.loads("[" * 65 + "]" * 65)
    assert strict_json.loads("[" * 64 + "]" * 64) is not None
    # Deeper than the interpreter's recursion limit: still a policy error, not a crash.
    with pytest.raises(strict_json.JsonPolicyError):
        strict_json.loads("[" * 100_000 + "]" * 100_000)
    assert strict_json.loads('{"x": 1.5e308}') == {"x": 1.5e308}


@pytest.mark.parametrize("number", ["1e999", "Infinity", "NaN"])
def test_cli_refuses_non_finite_budget_with_exit_2(tmp_path: Path, number: str) -> None:
    data = orders_to_json(load_example("search-and-sample"))
    data["goals"][0]["params"] = {"pd": 0.5}
    text = json.dumps(data).replace('"pd": 0.5', f'"pd": {number}')
    result = run_cli("validate", write(tmp_path, "orders.json", text.encode()))
    assert result.returncode == 2, result.stderr
    assert "$.goals[0].params.pd" in result.stderr
    assert "internal error" not in result.stderr


def test_a_value_that_keeps_the_policy_is_walked_without_paths(
        monkeypatch: pytest.MonkeyPatch) -> None:
    def no_paths(path: str, key: str) -> str:
        raise AssertionError("a path was built for a value that keeps the policy")

    monkeypatch.setattr(strict_json, "_key_path", no_paths)
    text = json.dumps(orders_to_json(load_example("search-and-sample")))
    assert strict_json.loads(text) == json.loads(text)
    strict_json.check([[1.5, {"a": 2**53 - 1}]] * 3, exact_integers=True)


@pytest.mark.parametrize(("value", "exact", "path"), [
    ({"a": [{"b": float("nan")}]}, False, '$.a[0].b'),
    ([{"n": 2**53}], True, "$[0].n"),
    (float("inf"), False, "$"),
    ({"x": [[[]]]}, False, "$.x[0][0]"),
])
def test_a_value_that_breaks_the_policy_is_named_by_its_path(
        value: object, exact: bool, path: str) -> None:
    with pytest.raises(strict_json.JsonPolicyError) as caught:
        strict_json.check(value, max_depth=3, exact_integers=exact)
    assert caught.value.path == path
    # Within the policy without exact integers, or with room to nest.
    if exact:
        strict_json.check(value, max_depth=3)


def test_a_body_that_keeps_the_policy_is_checked_without_a_walk_of_its_numbers(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A 1,000-goal draft has some 130,000 keys and items: its numbers are judged as they
    are parsed, and the walk after parsing visits only the containers, for their depth."""
    def no_walk(*args: object) -> bool:
        raise AssertionError("the numbers of a value that keeps the policy were walked")

    text = json.dumps(orders_to_json(load_example("search-and-sample")))
    monkeypatch.setattr(strict_json, "_conforms", no_walk)
    monkeypatch.setattr(strict_json, "_breaks", no_walk)
    assert strict_json.loads(text) == json.loads(text)
    assert strict_json.loads("1e308") == 1e308
    monkeypatch.undo()  # a value that breaks it is walked again, for the path
    with pytest.raises(strict_json.JsonPolicyError) as caught:
        strict_json.loads("-1e999")
    assert caught.value.path == "$"
    with pytest.raises(strict_json.JsonPolicyError, match="'b' appears twice"):
        strict_json.loads('{"a": {"b": 1, "c": 2, "b": 3}}')
