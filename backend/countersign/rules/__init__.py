"""Contingency rules: normal default theories for goal reasoning and safety (seed 004).

Public API (other packages depend on these names):

    parse_theory(data) -> DefaultTheory          read a `rules` object (TheoryError on bad input)
    theory_for(orders) -> DefaultTheory | None   orders rules merged with the vehicle profile's
    extension(theory, observations) -> Extension
    check_action(theory_or_ext, extension, planned_action) -> ActionVerdict   (eq. 17)
    design_findings(theory, orders=None) -> list[Finding]                     (section IV-B)
    plain_rules(theory) -> list[str]
"""

from .action import ActionVerdict, check_action
from .design import design_findings
from .engine import Extension, TheoryTooLarge, extension, parse_observations
from .examples import load_theory, theory_names
from .plain import plain_rules
from .theory import DefaultTheory, Rule, TheoryError, parse_theory, theory_for

__all__ = [
    "ActionVerdict",
    "DefaultTheory",
    "Extension",
    "Rule",
    "TheoryError",
    "TheoryTooLarge",
    "check_action",
    "design_findings",
    "extension",
    "load_theory",
    "parse_observations",
    "parse_theory",
    "plain_rules",
    "theory_for",
    "theory_names",
]
