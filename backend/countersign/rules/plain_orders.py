"""Plain-language orders with their contingency rules, for the supervisor.

`orders` must not import `rules` (dependencies point inward), so the rules join the orders'
plain writer here; the CLI `export --format plain`, the export route and the review route all
call this one module, so the supervisor reads the same sentences everywhere.
"""

from __future__ import annotations

from ..orders.model import Orders
from ..orders.team import plain_team
from ..orders.writers import write
from .plain import plain_rules
from .theory import TheoryError, theory_for

SECTION = "Contingency rules"


def rules_sentences(orders: Orders) -> list[str]:
    """The orders' (and target vehicle's) rules as one English sentence each; an empty list
    when there are none or when they cannot be read (the RULES finding reports that)."""
    try:
        theory = theory_for(orders)
    except TheoryError:
        return []
    return plain_rules(theory) if theory is not None else []


def rules_section(sentences: list[str]) -> str:
    """The "Contingency rules" section of the plain orders ('' when there are no rules)."""
    if not sentences:
        return ""
    return f"{SECTION}\n\n" + "".join(f"{sentence}\n" for sentence in sentences)


def plain_orders_with_rules(orders: Orders, sentences: list[str] | None = None) -> str:
    """The orders' plain writer, then the contingency rules section when they carry rules."""
    text = write(orders, "plain")
    section = rules_section(rules_sentences(orders) if sentences is None else sentences)
    return f"{text}\n{section}" if section else text


def write_for_supervisor(orders: Orders, fmt: str) -> str:
    """`orders.writers.write`, with the contingency rules appended to the plain format; a
    team's plain orders are each vehicle's, after the meeting points side by side."""
    if fmt == "plain" and orders.team is not None:
        return plain_team(orders, plain_orders_with_rules)
    return plain_orders_with_rules(orders) if fmt == "plain" else write(orders, fmt)
