"""Contingency rules (seed 004): scenarios, eq. 17, design findings, reading and the CLI."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import example_bytes, load_example
from countersign.orders.model import Orders
from countersign.orders.reader import read_json
from countersign.rules import (
    DefaultTheory,
    TheoryError,
    check_action,
    design_findings,
    extension,
    load_theory,
    parse_theory,
    plain_rules,
    theory_for,
)
from countersign.verify import validate
from countersign.verify.rules_design import rules_findings

from ..cli.test_bad_input import run_cli

# Everything the transect vehicle observes each period, in the nominal state.
NOMINAL: dict[str, bool] = {
    "at(home)": False, "on_surface": False, "gps_was_captured": True,
    "usbl_was_captured": True, "usbl_captured": True, "localisation_precision_low": False,
    "battery_low": False, "battery_critical": False, "camera_fault": False,
    "altitude_low": False, "surface_contact_close": False,
    "safety_sensor_failure(leak)": False, "transect_done(t1)": False,
    "transect_done(t2)": False, "mission_time_over": False,
}


def observe(**changes: bool) -> dict[str, bool]:
    names = {
        "t1_done": "transect_done(t1)", "t2_done": "transect_done(t2)",
        "leak": "safety_sensor_failure(leak)", "at_home": "at(home)",
    }
    result = dict(NOMINAL)
    result.update({names.get(key, key): value for key, value in changes.items()})
    return result


@pytest.fixture(scope="module")
def transect() -> DefaultTheory:
    return load_theory("transect")


@pytest.fixture(scope="module")
def exemplar() -> DefaultTheory:
    return load_theory("search-and-sample")


# ---------------------------------------------------------------- seed 004 transect scenario


def test_transect_theory_has_the_size_of_the_paper(transect: DefaultTheory) -> None:
    assert len(transect) == 44
    assert len(transect.defaults) == 17 and len(transect.strict) + len(transect.facts) == 27
    assert design_findings(transect) == []
    # Every derived literal and satisfied prerequisite counts: at least one per literal.
    ext = extension(transect, observe())
    assert ext.inferences >= len(ext.literals) > len(NOMINAL)


def test_transect_scenario_second_transect_abandoned_and_vehicle_goes_home(
    transect: DefaultTheory,
) -> None:
    # At home, on the surface, GPS fix: the mission objective is the first transect only.
    start = extension(transect, observe(at_home=True, on_surface=True))
    assert start.goals == ("transect_t1",) and start.safe_actions == ()
    assert check_action(transect, start, "goto_t1").allowed

    first = extension(transect, observe())
    assert first.holds("localised") and first.goals == ("transect_t1",)
    verdict = check_action(transect, first, "transect_t1")
    assert (verdict.allowed, verdict.action_to_take) == (True, "transect_t1")

    second = extension(transect, observe(t1_done=True))
    assert second.goals == ("transect_t2",)
    assert check_action(transect, second, "transect_t2").allowed

    # During the second transect localisation precision drops: not localised (seed 004 V-A).
    lost = extension(transect, observe(t1_done=True, localisation_precision_low=True))
    assert lost.holds("not localised") and not lost.holds("localised")
    assert "D_loc" in lost.blocked and "X_precision" in lost.fired
    assert lost.holds("not goal(transect_t2)") and "G_t2" in lost.blocked
    assert lost.goals == ("home",)
    verdict = check_action(transect, lost, "transect_t2")
    assert not verdict.allowed
    assert verdict.action_to_take == "go_home"
    assert "X_abandon" in verdict.because and "X_precision" in verdict.because
    assert "transect_t2" in verdict.explanation and "go_home" in verdict.explanation
    # Going home is what the rules now allow.
    assert check_action(transect, lost, "go_home").allowed

    # At home the mission has no goal left.
    home = extension(
        transect, observe(t1_done=True, localisation_precision_low=True, at_home=True)
    )
    assert home.goals == ()


def test_transect_never_georeferenced_means_not_localised(transect: DefaultTheory) -> None:
    ext = extension(transect, observe(gps_was_captured=False, usbl_was_captured=False))
    assert ext.holds("not localised") and "X_loc" in ext.fired
    only_usbl = extension(transect, observe(gps_was_captured=False))
    assert only_usbl.holds("localised")


def test_transect_energy_exception_eq18(transect: DefaultTheory) -> None:
    ext = extension(transect, {**observe(), "enough_energy(transect_t1)": False})
    verdict = check_action(transect, ext, "transect_t1")
    assert (verdict.allowed, verdict.action_to_take) == (False, "go_boat")
    assert verdict.because[0] == "X_energy"


def test_transect_leak_surfaces_and_never_dives(transect: DefaultTheory) -> None:
    ext = extension(transect, observe(leak=True, on_surface=True, surface_contact_close=True))
    assert "surface" in ext.safe_actions and "dive" not in ext.safe_actions
    assert "shutdown" not in ext.safe_actions
    assert {"S_sensor", "S_contact"} <= set(ext.blocked)


# ---------------------------------------------------------------------- exemplar's rules


def test_exemplar_leak_means_surface_not_shutdown(exemplar: DefaultTheory) -> None:
    ext = extension(exemplar, {"safety_sensor_failure(leak)": True})
    assert ext.safe_actions == ("surface",)
    assert ext.holds("not do_safe(shutdown)") and "S_shutdown" in ext.blocked
    verdict = check_action(exemplar, ext, "area_search")
    assert (verdict.allowed, verdict.action_to_take) == (False, "surface")
    assert verdict.because == ("S_leak_surface",)


def test_exemplar_other_safety_sensor_failure_means_shutdown(exemplar: DefaultTheory) -> None:
    for sensor in ("pressure", "temperature"):
        ext = extension(exemplar, {f"safety_sensor_failure({sensor})": True})
        assert ext.safe_actions == ("shutdown",), sensor
        assert "S_shutdown" in ext.fired
        verdict = check_action(exemplar, ext, "sample")
        assert verdict.action_to_take == "shutdown" and not verdict.allowed
    both = extension(
        exemplar,
        {"safety_sensor_failure(pressure)": True, "safety_sensor_failure(leak)": True},
    )
    assert both.safe_actions == ("surface",), "the leak exception wins over the default"


def test_exemplar_localisation(exemplar: DefaultTheory) -> None:
    lost = extension(exemplar, {"gps_was_captured": False, "usbl_was_captured": False})
    assert lost.holds("not localised") and lost.goals == ("return_to_base",)
    assert "E_localised" in lost.blocked and "E_no_fix" in lost.fired
    for fixes in ({"gps_was_captured": True, "usbl_was_captured": False},
                  {"gps_was_captured": False, "usbl_was_captured": True}, {}):
        ext = extension(exemplar, fixes)
        assert ext.holds("localised"), fixes
        assert ext.goals == ("mission_complete",)
    assert check_action(exemplar, extension(exemplar, {}), "area_search").allowed


def test_exception_without_alternative_refuses_the_action() -> None:
    theory = parse_theory({
        "observables": ["sea_state_high"], "actions": ["sample"],
        "strict": [{"id": "X1", "kind": "action", "if": ["next_action(sample)",
                    "sea_state_high"], "then": "not do_safe(sample)"}],
    })
    ext = extension(theory, {"sea_state_high": True})
    verdict = check_action(theory, ext, "sample")
    assert (verdict.allowed, verdict.action_to_take) == (False, None)
    assert verdict.because == ("X1",) and "refused" in verdict.explanation
    # The extension itself may be passed as the first argument.
    assert check_action(ext, extension(theory, {}), "sample").allowed


def test_contradictory_observations_are_reported_not_fatal(exemplar: DefaultTheory) -> None:
    ext = extension(exemplar, {"gps_was_captured": True, "not gps_was_captured": True,
                               "safety_sensor_failure(pressure)": True})
    assert ext.contradictions == ("gps_was_captured",) and not ext.consistent
    assert ext.safe_actions == ("shutdown",), "safety rules still act"
    verdict = check_action(exemplar, ext, "sample")
    assert "Contradictory" in verdict.explanation
    # A contradiction derived by a strict rule from observations.
    theory = parse_theory({"observables": ["p", "q"], "strict": [
        {"id": "S1", "if": ["p"], "then": "not q"}]})
    ext = extension(theory, {"p": True, "q": True})
    assert ext.contradictions == ("q",)
    # Observed atoms that no rule mentions are carried along, contradictions included.
    ext = extension(theory, {"z": True, "not z": True})
    assert ext.contradictions == ("z",) and ext.holds("z") and ext.holds("not z")


def test_priorities_and_specificity() -> None:
    theory = parse_theory({"observables": ["bird", "penguin"], "defaults": [
        {"id": "D1", "if": ["bird"], "then": "flies"},
        {"id": "D2", "if": ["bird", "penguin"], "then": "not flies"},
        {"id": "D3", "then": "calm"},
        {"id": "D4", "then": "not calm", "priority": 1},
    ]})
    ext = extension(theory, {"bird": True, "penguin": True})
    assert ext.holds("not flies") and ext.blocked == ("D1", "D3")
    assert ext.fired == ("D4", "D2")
    assert extension(theory, {"bird": True}).holds("flies")


def test_extension_of_the_theory_of_many_sensors_grounds_variables(
    exemplar: DefaultTheory,
) -> None:
    observations = {f"safety_sensor_failure(s{i})": i == 7 for i in range(20)}
    ext = extension(exemplar, observations)
    assert ext.safe_actions == ("shutdown",)
    assert extension(exemplar, {k: False for k in observations}).safe_actions == ()


# ------------------------------------------------------------------------------- reading


@pytest.mark.parametrize(
    ("data", "path"),
    [
        ({"defaults": [{"id": "D1", "then": "a"}, {"id": "D2", "if": ["b c"], "then": "a"}]},
         "rules.defaults[1].if[0]"),
        ({"strict": [{"id": "S1", "if": ["a"]}]}, "rules.strict[0].then"),
        ({"strict": [{"id": "S1", "then": "a", "iff": []}]}, "rules.strict[0].iff"),
        ({"default": []}, "rules.default"),
        ({"defaults": [{"id": "D1", "then": "a"}, {"id": "D1", "then": "b"}]},
         "rules.defaults[1].id"),
        ({"defaults": [{"id": "D1", "then": "a", "kind": "emergency"}]},
         "rules.defaults[0].kind"),
        ({"defaults": [{"id": "D1", "then": "a", "priority": True}]},
         "rules.defaults[0].priority"),
        ({"defaults": {"id": "D1"}}, "rules.defaults"),
        ({"defaults": ["a"]}, "rules.defaults[0]"),
        ({"facts": [{"id": "F1", "fact": "at(X)"}]}, "rules.facts[0].fact"),
        ({"observables": ["not gps"]}, "rules.observables[0]"),
        ({"actions": ["go home"]}, "rules.actions[0]"),
        ({"defaults": [{"id": "D 1", "then": "a"}]}, "rules.defaults[0].id"),
        ({"strict": [{"id": "S1", "if": ["p(X)", "q(Y)", "r(Z)"], "then": "s"}]},
         "rules.strict[0]"),
        ({"strict": [{"id": "S1", "then": "__import__('os')"}]}, "rules.strict[0].then"),
        ({"strict": [{"id": "S1", "then": 3}]}, "rules.strict[0].then"),
    ],
)
def test_parse_errors_name_the_json_path(data: dict[str, Any], path: str) -> None:
    with pytest.raises(TheoryError) as caught:
        parse_theory(data)
    assert caught.value.path == path, caught.value
    assert isinstance(caught.value, ValueError) and str(caught.value).startswith(path)


def test_parse_reads_literals_and_writes_plain_english(exemplar: DefaultTheory) -> None:
    theory = parse_theory({"strict": [{"id": "S1", "if": ["not  gps", "¬usbl(x)"],
                                       "then": "~ localised", "text": "why"}]})
    rule = theory.rule("S1")
    assert [str(b) for b in rule.body] == ["not gps", "not usbl(x)"]
    assert str(rule.head) == "not localised" and rule.formula() == (
        "not gps and not usbl(x) -> not localised")
    sentences = plain_rules(exemplar)
    assert len(sentences) == len(exemplar)
    by_id = {s.split(" ", 1)[0]: s for s in sentences}
    assert "shut down" in by_id["S_shutdown"].lower() or "shutdown" in by_id["S_shutdown"]
    assert by_id["S_shutdown"].startswith("S_shutdown (safety default): For any X: normally")
    assert "surface now" in by_id["S_leak_surface"]
    assert "neither a GPS nor a USBL fix" in by_id["E_no_fix"]
    assert by_id["E_no_fix"].startswith(
        "E_no_fix (estimation rule): If 'gps was captured' is false and 'usbl was captured' "
        "is false, then 'localised' is false.")
    assert by_id["A_energy"].startswith(
        "A_energy (action check rule): For any X: if the planned action is X and "
        "'enough energy (X)' is false, then transit now.")


# ----------------------------------------------------------------------------- orders


def test_rules_in_orders_keep_old_digests_and_round_trip() -> None:
    plain = load_example("search-and-sample")
    assert plain.rules is None and theory_for(plain) is None
    # The digest of the built-in exemplar is pinned by the acceptance: unchanged.
    assert digest(plain) == digest(read_json(example_bytes("search-and-sample")))
    assert "rules" not in orders_to_json(plain)
    with_rules = load_example("search-and-sample-rules")
    data = orders_to_json(with_rules)
    assert data["rules"]["strict"][0]["if"] == ["not gps_was_captured", "not usbl_was_captured"]
    assert digest(read_json(json.dumps(data).encode())) == digest(with_rules)


def test_shipped_orders_carry_the_shipped_theories() -> None:
    for example, theory_name in (("search-and-sample-rules", "search-and-sample"),
                                 ("transect-survey", "transect")):
        orders = load_example(example)
        theory = theory_for(orders)
        assert theory is not None
        assert theory.rules == load_theory(theory_name).rules
        assert design_findings(theory, orders) == []
        report = validate(orders)
        assert report.ok and report.findings == [], report.findings
    transect_report = validate(load_example("transect-survey"))
    assert transect_report.paths is not None and transect_report.paths.total == 39


def _orders(rules: dict[str, Any] | None = None, vehicle_rules: dict[str, Any] | None = None,
            behaviors: list[str] | None = None) -> Orders:
    vehicle: dict[str, Any] = {"id": "v", "behaviors": behaviors or ["transit", "surface"]}
    if vehicle_rules is not None:
        vehicle["rules"] = vehicle_rules
    data: dict[str, Any] = {"id": "m", "vehicle": "v", "start": "G1", "goals": [
        {"id": "G1", "behavior": "transit", "requires": ["transit"],
         "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
        "vehicles": [vehicle]}
    if rules is not None:
        data["rules"] = rules
    return Orders.model_validate(data)


def test_theory_for_merges_vehicle_profile_and_orders() -> None:
    vehicle_rules = {"observables": ["leak"], "strict": [
        {"id": "V1", "kind": "safety", "if": ["leak"], "then": "do_safe(surface)"}]}
    orders_rules = {"observables": ["gps"], "defaults": [{"id": "O1", "then": "localised"}],
                    "strict": [{"id": "O2", "if": ["not gps"], "then": "not localised"}]}
    theory = theory_for(_orders(orders_rules, vehicle_rules))
    assert theory is not None
    assert [r.id for r in theory.rules] == ["V1", "O2", "O1"]
    assert theory.sources == ("vehicles[0].rules", "rules")
    ext = extension(theory, {"leak": True, "gps": False})
    assert ext.safe_actions == ("surface",) and ext.holds("not localised")
    with pytest.raises(TheoryError) as caught:
        theory_for(_orders({"defaults": [{"id": "V1", "then": "x"}]}, vehicle_rules))
    assert caught.value.path == "rules.defaults[0]"


def test_bad_rules_in_orders_are_a_rules_finding_not_a_read_error(tmp_path: Path) -> None:
    orders = _orders({"defaults": [{"id": "D1", "then": "do_safe(surface"}]})
    findings = rules_findings(orders)
    assert [(f.code, f.severity, f.subjects) for f in findings] == [
        ("RULES", "error", ("rules.defaults[0].then",))]
    report = validate(orders)
    assert not report.ok and report.findings[-1].code == "RULES"
    path = tmp_path / "bad-rules.json"
    path.write_text(json.dumps(orders_to_json(orders)))
    result = run_cli("validate", str(path))
    assert result.returncode == 1 and "RULES" in result.stdout
    assert "rules.defaults[0].then" in result.stdout


# ----------------------------------------------------------------------- design findings


def _codes(theory_data: dict[str, Any], orders: Orders | None = None) -> dict[str, str]:
    """Subjects (joined) -> severity of every RULES finding."""
    findings = design_findings(parse_theory(theory_data), orders)
    assert all(f.code == "RULES" for f in findings)
    return {",".join(f.subjects): f.severity for f in findings}


BASE: dict[str, Any] = {"observables": ["leak", "gps", "usbl", "sensor_failure(X)"],
                        "actions": ["surface", "shutdown"]}


def test_design_safety_default_without_exception_path() -> None:
    found = _codes({**BASE, "defaults": [
        {"id": "S1", "kind": "safety", "if": ["sensor_failure(X)"],
         "then": "do_safe(shutdown)"}]})
    assert found == {"S1": "warning"}
    fixed = _codes({**BASE, "defaults": [
        {"id": "S1", "kind": "safety", "if": ["sensor_failure(X)"],
         "then": "do_safe(shutdown)"}], "strict": [
        {"id": "X1", "kind": "safety", "if": ["sensor_failure(leak)"],
         "then": "not do_safe(shutdown)", "exception_to": ["S1"]}]})
    assert fixed == {}


def test_design_estimation_default_nothing_can_defeat() -> None:
    assert _codes({**BASE, "defaults": [{"id": "E1", "then": "localised"}]}) == {
        "E1": "warning"}


def test_design_estimation_must_not_conclude_observations() -> None:
    found = _codes({**BASE, "strict": [{"id": "E1", "if": ["usbl"], "then": "gps"}]})
    assert found == {"E1": "warning"}


def test_design_safety_and_goal_patterns() -> None:
    found = _codes({**BASE, "defaults": [
        {"id": "S1", "kind": "safety", "if": ["leak"], "then": "surfaced"},
        {"id": "S2", "kind": "safety", "if": ["leak"], "then": "not do_safe(surface)"},
        {"id": "G1", "kind": "goal", "if": ["leak"], "then": "do_safe(surface)"},
        {"id": "G2", "kind": "goal", "if": ["leak"], "then": "home"},
    ], "strict": [{"id": "X", "if": ["gps"], "then": "not surfaced"},
                  {"id": "Y", "if": ["gps"], "then": "not home"}]})
    assert found["S1"] == "error" and found["S2"] == "error" and found["G1"] == "error"
    assert found["G2"] == "warning"
    reads_goal = _codes({**BASE, "strict": [
        {"id": "S1", "kind": "safety", "if": ["goal(survey)", "leak"], "then": "do_safe(surface)"},
        {"id": "G1", "kind": "goal", "if": ["gps"], "then": "goal(survey)"}]})
    assert reads_goal == {"S1": "warning"}


def test_design_unknown_action_against_the_vehicle() -> None:
    rules = {**BASE, "actions": ["surface", "teleport"], "strict": [
        {"id": "X1", "kind": "safety", "if": ["leak"], "then": "do_safe(teleport)"}]}
    assert _codes(rules) == {}
    orders = _orders(rules)
    found = design_findings(parse_theory(rules), orders)
    assert [(f.subjects, f.severity) for f in found] == [(("X1",), "error")]
    assert "teleport" in found[0].message and "vehicle v" in found[0].message
    assert rules_findings(orders) == found
    no_actions = {"observables": ["leak"], "strict": [
        {"id": "X1", "kind": "safety", "if": ["leak"], "then": "do_safe(surface)"}]}
    assert _codes(no_actions) == {"X1": "warning"}


def test_design_rules_reading_atoms_nothing_produces() -> None:
    found = _codes({**BASE, "strict": [
        {"id": "X1", "kind": "safety", "if": ["leak", "water_ingress"],
         "then": "do_safe(surface)"},
        {"id": "X2", "kind": "safety", "if": ["sensor_failure(pressure)"],
         "then": "do_safe(shutdown)"}]})
    assert found == {"X1": "warning"}
    assert _codes({"strict": [{"id": "X1", "if": ["a"], "then": "b"}]}) == {"rules": "warning"}
    assert _codes({**BASE, "defaults": [{"id": "D1", "if": ["gps", "not gps"],
                                         "then": "do_safe(surface)", "kind": "safety"}],
                   "strict": [{"id": "X", "if": ["leak"], "then": "not do_safe(surface)",
                               "kind": "safety"}]}) == {"D1": "warning"}


def test_design_shadowed_and_conflicting_rules() -> None:
    found = _codes({**BASE, "facts": [{"id": "F1", "fact": "not calm"}], "defaults": [
        {"id": "D1", "then": "calm"},
        {"id": "D2", "if": ["gps"], "then": "fast"},
        {"id": "D3", "if": ["gps"], "then": "not fast"},
    ], "strict": [
        {"id": "X1", "if": ["usbl"], "then": "deep"},
        {"id": "X2", "if": ["usbl"], "then": "not deep"},
        {"id": "X3", "if": ["leak"], "then": "not calm", "exception_to": ["D9"]},
        {"id": "X4", "if": ["leak"], "then": "quiet", "exception_to": ["D1"]},
    ]})
    assert found["D1,F1"] == "warning"
    assert found["D2,D3"] == "warning"
    assert found["X1,X2"] == "error"
    assert found["X3"] == "error"
    assert found["X4,D1"] == "warning"


def test_design_goal_conflicting_with_safety() -> None:
    found = _codes({**BASE, "defaults": [{"id": "G1", "kind": "goal", "then": "goal(survey)"}],
                    "strict": [{"id": "S1", "kind": "safety", "if": ["leak"],
                                "then": "not goal(survey)"}]})
    assert found["G1,S1"] == "warning" and found["S1"] == "error"


# ------------------------------------------------------------------------------------ CLI


def test_cli_rules_text_shows_rules_extension_and_verdict() -> None:
    result = run_cli("rules", "example:transect-survey", "--observe",
                     "transect_done(t1),localisation_precision_low=true,gps_was_captured=1",
                     "--action", "transect_t2")
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "Rules of example:transect-survey (44: 17 defaults" in out
    assert "D_loc (estimation default): Normally, 'localised' is true, unless" in out
    assert "goals:   home" in out and "blocked: D_loc, G_t1, G_t2" in out
    assert "Planned action transect_t2: overridden: do go_home" in out


def test_cli_rules_json_and_theory_files(tmp_path: Path) -> None:
    result = run_cli("rules", "theory:search-and-sample", "--observe",
                     "safety_sensor_failure(leak)", "--action", "sample", "--format", "json")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["extension"]["safe_actions"] == ["surface"]
    assert data["verdict"] == {"planned": "sample", "allowed": False,
                               "action_to_take": "surface", "because": ["S_leak_surface"],
                               "explanation": data["verdict"]["explanation"]}
    assert {r["id"] for r in data["rules"]} >= {"S_leak", "E_localised"}
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"rules": {"strict": [{"id": "S1", "then": "a b"}]}}))
    result = run_cli("rules", str(bad))
    assert result.returncode == 2 and "rules.strict[0].then" in result.stderr
    design_error = tmp_path / "design.json"
    design_error.write_text(json.dumps({"defaults": [
        {"id": "S1", "kind": "safety", "then": "surfaced"}]}))
    result = run_cli("rules", str(design_error))
    assert result.returncode == 1 and "RULES [S1]" in result.stdout
    assert run_cli("rules", "example:search-and-sample").returncode == 2
    assert run_cli("rules", str(tmp_path / "missing.json")).returncode == 2
    result = run_cli("rules", "theory:transect", "--observe", "gps=maybe")
    assert result.returncode == 2 and "--observe" in result.stderr
    help_text = run_cli("rules", "--help").stdout
    assert "(17)" in help_text and "--observe" in help_text and "theory:transect" in help_text


def test_extensions_from_many_threads_agree_with_serial(transect: DefaultTheory) -> None:
    # Rehearsals step shared theories from several threads: the compiled program is shared.
    from concurrent.futures import ThreadPoolExecutor

    fresh = load_theory("transect")  # nothing compiled yet: threads race to compile it
    cases = [observe(t1_done=bool(i % 2), localisation_precision_low=i % 3 == 0,
                     leak=i % 5 == 0) for i in range(40)]
    cases += [{**case, f"safety_sensor_failure(s{i})": True} for i, case in enumerate(cases)]
    serial = [extension(transect, case).to_json() for case in cases]
    with ThreadPoolExecutor(max_workers=8) as pool:
        parallel = list(pool.map(lambda case: extension(fresh, case).to_json(), cases))
    assert parallel == serial
    assert serial[0]["derived_by"]["not goal(transect_t2)"] in {"X_order", "X_t2_lost"}


def test_grounding_is_bounded() -> None:
    from countersign.rules.engine import MAX_GROUND_RULES, TheoryTooLarge

    constants = [{"id": f"F{i}", "fact": f"p(c{i})"} for i in range(1_000)]
    theory = parse_theory({"facts": constants, "strict": [
        {"id": "S1", "if": ["p(X)", "p(Y)"], "then": "q(X)"}]})
    assert MAX_GROUND_RULES < 1_000 * 1_000
    with pytest.raises(TheoryTooLarge, match=r"rules\.strict"):
        extension(theory, {})
