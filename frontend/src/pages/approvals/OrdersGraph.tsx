/**
 * A read-only drawing of the orders' goal graph for the review and audit pages: the mission
 * editor's pure graph and layout code (editor/graph.ts, editor/layout.ts) drawn as SVG, with a
 * text list of every transition beside it for keyboard and screen reader users. Laid out like
 * the editor (ELK layered in a worker, long chains wrapped), opened fitted to its frame, with
 * zoom buttons; each edge carries its outcome letter.
 */
import { useEffect, useId, useLayoutEffect, useMemo, useRef, useState } from "react";

import { type Layout, type Orders, ordersToGraph, OUTCOME_LABEL, OUTCOME_LETTER } from "../../editor/graph";
import { layeredLayout, GOAL_SIZE, TERMINAL_SIZE } from "../../editor/layout";
import { layoutOffThread } from "../../editor/layoutClient";

const ASPECT = 1.6;
/** Never drawn smaller than this: 13 px titles stay at least 7 px (the zoom buttons enlarge). */
const MIN_FIT = 0.55;
const ZOOMS = [0.25, 0.35, 0.5, 0.65, 0.8, 1, 1.25, 1.5, 2];

const PAD = 20;

/** A label cut to what its box holds (a goal 220 px, a terminal 160 px, 13 px text). */
function shorten(label: string, max: number): string {
  return label.length > max ? `${label.slice(0, max - 1)}…` : label;
}
const COLORS: Record<string, string> = { succeed: "#1a7f37", fail: "#b35900", violate: "#b42318" };

export function OrdersGraph({ orders: o, label }: { orders: Orders; label: string }) {
  const [layout, setLayout] = useState<Layout>(() => layeredLayout(o, ASPECT));
  // One page may draw several graphs (a team's members, refinements): ids stay unique.
  const arrow = `arrow${useId().replace(/[^A-Za-z0-9]/g, "")}`;
  useEffect(() => {
    let current = true;
    layoutOffThread(o, {}, ASPECT).then((l) => current && setLayout(l), () => undefined);
    return () => {
      current = false;
    };
  }, [o]);
  const graph = useMemo(() => ordersToGraph(o, layout), [o, layout]);
  // A team's rendezvous goals name their meeting; a refined goal's steps are drawn below.
  const meets = useMemo(() => new Map((o.goals ?? []).filter((g) => g.meet).map((g) => [g.id, g.meet!])), [o]);
  const refined = useMemo(() => new Set((o.goals ?? []).filter((g) => g.refines).map((g) => g.id)), [o]);
  const frame = useRef<HTMLDivElement>(null);
  const [zoom, setZoom] = useState<number | null>(null);
  const [fit, setFit] = useState(1);
  const size = (kind: string) => (kind === "goal" ? GOAL_SIZE : TERMINAL_SIZE);
  const byId = new Map(graph.nodes.map((n) => [n.id, n]));
  const width = Math.max(...graph.nodes.map((n) => n.position.x + size(n.kind).width), 200) + 2 * PAD;
  const height = Math.max(...graph.nodes.map((n) => n.position.y + size(n.kind).height), 100) + 2 * PAD;
  useLayoutEffect(() => {
    const w = frame.current?.clientWidth ?? width;
    setFit(Math.max(MIN_FIT, Math.min(1, (w - 4) / width)));
  }, [width]);
  const scale = zoom ?? fit;
  const step = (dir: 1 | -1) => {
    const next = dir > 0 ? ZOOMS.find((z) => z > scale + 0.01) : [...ZOOMS].reverse().find((z) => z < scale - 0.01);
    if (next) setZoom(next);
  };
  return (
    <figure className="orders-graph">
      <div className="orders-graph-tools" role="toolbar" aria-label="Graph zoom">
        <button type="button" onClick={() => setZoom(null)}>
          Fit
        </button>
        <button type="button" onClick={() => step(-1)} aria-label="Zoom out">
          −
        </button>
        <button type="button" onClick={() => step(1)} aria-label="Zoom in">
          +
        </button>
        <span data-testid="orders-graph-zoom">{Math.round(scale * 100)}%</span>
      </div>
      <div className="orders-graph-canvas" ref={frame} role="region" tabIndex={0} aria-label={`${label} (scrollable)`}>
        <svg
          width={Math.round(width * scale)}
          height={Math.round(height * scale)}
          viewBox={`${-PAD} ${-PAD} ${width} ${height}`}
          role="img"
          aria-label={`${label}: ${graph.nodes.length} goals and terminals, ${graph.edges.length} transitions`}
          data-testid="orders-graph"
        >
          <defs>
            <marker id={arrow} viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse">
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
            // The outcome letter near the start of the edge, where edges of one goal are apart.
            const lx = x1 + 14;
            const ly = y1 - 4;
            return (
              <g key={e.id} data-testid={`orders-edge-${e.id}`}>
                <path d={d} fill="none" stroke={COLORS[e.outcome]} strokeWidth={1.5} markerEnd={`url(#${arrow})`} opacity={0.8} />
                <text x={lx} y={ly} fontSize={12} fontWeight={700} fill={COLORS[e.outcome]} className="orders-edge-letter">
                  {OUTCOME_LETTER[e.outcome]}
                </text>
              </g>
            );
          })}
          {graph.nodes.map((n) => {
            const s = size(n.kind);
            return (
              <g key={n.id} transform={`translate(${n.position.x} ${n.position.y})`}>
                <title>{`${n.id}: ${n.label}`}</title>
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
                  {shorten(n.label, n.kind === "goal" ? 28 : 19)}
                </text>
                {meets.get(n.id) && (
                  <text x={10} y={62} fontSize={12} fontWeight={700} fill="#6b3fa0" data-testid={`orders-meet-${n.id}`}>
                    meet {meets.get(n.id)}
                  </text>
                )}
                {refined.has(n.id) && (
                  <text x={10} y={meets.get(n.id) ? 82 : 62} fontSize={12} fontWeight={700} fill="#1f4f99">
                    refined: steps below
                  </text>
                )}
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
