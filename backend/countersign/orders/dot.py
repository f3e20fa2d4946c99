"""Graphviz DOT view of mission orders, drawn like seed 000 Figure 4: goals as boxes, the
three outcomes as coloured edges, terminals coloured by kind.

Every id and label is written as an escaped double-quoted string, so no title can break the
output or inject statements. Defects stay visible: an unknown target becomes a dashed red
"? id" node, and a missing outcome simply has no edge.
"""

from __future__ import annotations

from .model import OUTCOMES, Goal, Orders, Terminal

EDGE_STYLE: dict[str, tuple[str, str]] = {
    # outcome: (colour, label)
    "succeed": ("forestgreen", "s"),
    "fail": ("darkorange", "f"),
    "violate": ("red", "c"),
}
TERMINAL_STYLE: dict[str, tuple[str, str]] = {
    # kind: (line colour, fill colour)
    "complete": ("forestgreen", "palegreen"),
    "abort": ("red", "mistyrose"),
}
# Neither name can be an id of the orders: ids never contain "(" or "?".
START_NODE = "(start)"
UNKNOWN_PREFIX = "?"


def _escape(text: str) -> str:
    escaped = text.replace("\\", "\\\\").replace('"', '\\"')
    escaped = escaped.replace("\r\n", "\n").replace("\r", "\n").replace("\n", "\\n")
    # Other control characters have no business in a label; drop them.
    return "".join(ch for ch in escaped if ch >= " " or ch == "\t")


def quote(text: str) -> str:
    """`text` as a DOT double-quoted string; newlines become DOT's `\\n` line break."""
    return f'"{_escape(text)}"'


def _label(*lines: str) -> str:
    """Non-empty lines, each escaped, joined by DOT line breaks."""
    return quote("\n".join(line for line in lines if line))


def _attributes(**attributes: str) -> str:
    # Values are already DOT literals (quoted strings or bare keywords).
    return "[" + ", ".join(f"{key}={value}" for key, value in attributes.items()) + "]"


def to_dot(orders: Orders) -> str:
    """The orders as a DOT digraph named by the mission id."""
    goals = orders.goal_index()
    terminals = {t.id: t for t in orders.terminal_index().values() if t.id not in goals}
    starts = [orders.start] if isinstance(orders.start, str) else list(orders.start or [])

    title = _label(orders.title or orders.id)
    lines = [
        f"digraph {quote(orders.id)} {{",
        f"  graph {_attributes(rankdir='LR', label=title, labelloc='t')};",
        '  node [fontname="Helvetica"];',
        '  edge [fontname="Helvetica"];',
        *_element_nodes(goals, terminals, starts),
    ]
    unknown: list[str] = []
    edges = _edges(goals, terminals, starts, unknown)
    if starts:
        lines.append(
            f"  {quote(START_NODE)} "
            f"{_attributes(shape='point', width=quote('0.15'), label=quote(''))};"
        )
    for target in unknown:
        attrs = _attributes(
            shape="box",
            style='"dashed"',
            color='"red"',
            fontcolor='"red"',
            label=quote(f"? {target}"),
        )
        lines.append(f"  {quote(UNKNOWN_PREFIX + target)} {attrs};")
    lines.extend(edges)
    lines.append("}")
    return "\n".join(lines) + "\n"


def _element_nodes(goals: dict[str, Goal], terminals: dict[str, Terminal],
                   starts: list[str]) -> list[str]:
    """A node line per goal (a start in bold) and per terminal (coloured by its kind)."""
    lines = []
    for goal in goals.values():
        style = '"rounded,bold"' if goal.id in starts else '"rounded"'
        penwidth = '"2.5"' if goal.id in starts else '"1"'
        attrs = _attributes(
            shape="box", style=style, penwidth=penwidth, label=_label(goal.id, goal.title)
        )
        lines.append(f"  {quote(goal.id)} {attrs};")
    for terminal in terminals.values():
        colour, fill = TERMINAL_STYLE[terminal.kind]
        attrs = _attributes(
            shape="doubleoctagon",
            style='"filled"',
            color=quote(colour),
            fillcolor=quote(fill),
            label=_label(terminal.id, terminal.title),
        )
        lines.append(f"  {quote(terminal.id)} {attrs};")
    return lines


def _edges(goals: dict[str, Goal], terminals: dict[str, Terminal], starts: list[str],
           unknown: list[str]) -> list[str]:
    """The start's edges and every successor edge, coloured by outcome; a successor that is
    no goal or terminal goes to a node of its own, its name added to `unknown`."""

    def node_for(target: str) -> str:
        if target in goals or target in terminals:
            return quote(target)
        if target not in unknown:
            unknown.append(target)
        return quote(UNKNOWN_PREFIX + target)

    edges: list[str] = []
    for start in starts:
        edges.append(f"  {quote(START_NODE)} -> {node_for(start)};")
    for goal in goals.values():
        for outcome in OUTCOMES:
            colour, letter = EDGE_STYLE[outcome]
            for target in goal.successors(outcome):
                attrs = _attributes(
                    label=quote(letter), color=quote(colour), fontcolor=quote(colour)
                )
                edges.append(f"  {quote(goal.id)} -> {node_for(target)} {attrs};")
    return edges
