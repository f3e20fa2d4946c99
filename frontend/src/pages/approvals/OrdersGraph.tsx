/**
 * A read-only drawing of the orders' goal graph for the review and audit pages: the mission
 * editor's pure graph and layout code (editor/graph.ts, editor/layout.ts) drawn as SVG, with a
 * text list of every transition beside it for keyboard and screen reader users.
 */
import { useMemo } from "react";

import { type Orders, ordersToGraph, OUTCOME_LABEL, OUTCOME_LETTER } from "../../editor/graph";
import { fastLayout, GOAL_SIZE, TERMINAL_SIZE } from "../../editor/layout";

const PAD = 20;
const COLORS: Record<string, string> = { succeed: "#1a7f37", fail: "#b35900", violate: "#b42318" };

export function OrdersGraph({ orders, label }: { orders: Record<string, unknown>; label: string }) {
  const graph = useMemo(() => {
    const o = orders as unknown as Orders;
    return ordersToGraph(o, fastLayout(o));
  }, [orders]);
  const size = (kind: string) => (kind === "goal" ? GOAL_SIZE : TERMINAL_SIZE);
  const byId = new Map(graph.nodes.map((n) => [n.id, n]));
  const width = Math.max(...graph.nodes.map((n) => n.position.x + size(n.kind).width), 200) + 2 * PAD;
  const height = Math.max(...graph.nodes.map((n) => n.position.y + size(n.kind).height), 100) + 2 * PAD;
  return (
    <figure className="orders-graph">
      <div className="orders-graph-canvas" role="region" tabIndex={0} aria-label={`${label} (scrollable)`}>
        <svg
          width={width}
          height={height}
          viewBox={`${-PAD} ${-PAD} ${width} ${height}`}
          role="img"
          aria-label={`${label}: ${graph.nodes.length} goals and terminals, ${graph.edges.length} transitions`}
          data-testid="orders-graph"
        >
          <defs>
            <marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse">
              <path d="M 0 0 L 10 5 L 0 10 z" fill="#555" />
            </marker>
          </defs>
          {graph.edges.map((e, i) => {
            const from = byId.get(e.source);
            const to = byId.get(e.target);
            if (!from || !to) return null;
            const slot = { succeed: 0.25, fail: 0.5, violate: 0.75 }[e.outcome];
            const x1 = from.position.x + GOAL_SIZE.width;
            const y1 = from.position.y + GOAL_SIZE.height * slot;
            const x2 = to.position.x;
            const y2 = to.position.y + size(to.kind).height / 2;
            const bend = Math.max(40, Math.abs(x2 - x1) / 2);
            const d = x2 > x1 ? `M ${x1} ${y1} C ${x1 + bend} ${y1}, ${x2 - bend} ${y2}, ${x2} ${y2}` : `M ${x1} ${y1} C ${x1 + 80} ${y1 - 120 - i * 4}, ${x2 - 80} ${y2 - 120 - i * 4}, ${x2} ${y2}`;
            return <path key={e.id} d={d} fill="none" stroke={COLORS[e.outcome]} strokeWidth={1.5} markerEnd="url(#arrow)" opacity={0.8} />;
          })}
          {graph.nodes.map((n) => {
            const s = size(n.kind);
            return (
              <g key={n.id} transform={`translate(${n.position.x} ${n.position.y})`}>
                <rect
                  width={s.width}
                  height={s.height}
                  rx={n.kind === "goal" ? 6 : 20}
                  fill={n.kind === "goal" ? "#fff" : n.terminalKind === "abort" ? "#fde8e8" : "#e6f4ea"}
                  stroke={n.start ? "#1f4e99" : "#888"}
                  strokeWidth={n.start ? 2.5 : 1}
                />
                <text x={10} y={20} fontSize={12} fontFamily="monospace" fill="#333">
                  {n.id}
                  {n.start ? " · start" : ""}
                </text>
                <text x={10} y={40} fontSize={13} fill="#111">
                  {n.label.length > 28 ? `${n.label.slice(0, 27)}…` : n.label}
                </text>
              </g>
            );
          })}
        </svg>
      </div>
      <figcaption>
        <details>
          <summary>Transitions as text</summary>
          <ul className="transitions">
            {graph.edges.map((e) => (
              <li key={e.id}>
                <code>{e.source}</code> — {OUTCOME_LABEL[e.outcome]} ({OUTCOME_LETTER[e.outcome]}) → <code>{e.target}</code>
              </li>
            ))}
          </ul>
        </details>
      </figcaption>
    </figure>
  );
}
