/**
 * Auto layout. Up to ELK_MAX_GOALS (40) goals: ELK's layered algorithm (elkjs; Sugiyama with layer
 * sweep crossing minimisation and fixed port order, succeed above fail above violate), run in
 * the layout worker (layoutClient.ts), wrapped into bands at the canvas's aspect ratio. It was
 * measured against the linear layout below (crossings.test.ts prints the counts): fewer
 * edge crossings on Pirates and on a 100-goal mission. Larger orders, and a worker that does
 * not answer, get the linear layered layout: goals in columns by their longest distance from
 * the start, ordered by their predecessors' ports, linear time (ELK took seconds
 * there).
 */
import ELK, { type ElkExtendedEdge, type ElkNode } from "elkjs/lib/elk.bundled.js";

import { goals, type Layout, type Orders, OUTCOMES, successors, terminals } from "./graph";

/** The rendered sizes of nodes (styles.css: .goal-node is 220 x 112, .terminal-node 160 wide). */
export const GOAL_SIZE = { width: 220, height: 112 };
export const TERMINAL_SIZE = { width: 160, height: 72 };

/** Rendered sizes of nodes (React Flow's measurements), when known. */
export type Sizes = Record<string, { width: number; height: number }>;

/**
 * The layered layout: goals in columns by their longest distance
 * from the start (back edges of loops ignored), terminals in the last column, and inside a
 * column ordered by the mean position of their predecessors' outcome ports (s above f above c).
 */
// Length: one layered layout pass (ranks, order, coordinates) read top to bottom.
export function layeredLayout(orders: Orders, aspect?: number): Layout {
  const goalIds = [...new Set(goals(orders).map((g) => g.id))];
  const isGoal = new Set(goalIds);
  const out = new Map<string, { target: string; rank: number }[]>();
  for (const g of goals(orders)) {
    if (out.has(g.id)) continue;
    out.set(
      g.id,
      OUTCOMES.flatMap((o, i) => successors(g, o).filter((t) => isGoal.has(t)).map((t) => ({ target: t, rank: i / 3 }))),
    );
  }
  // Depth-first postorder from the start goal(s), then from any goal left over.
  const start = orders.start;
  const roots = [...(Array.isArray(start) ? start : start ? [start] : []).filter((s) => isGoal.has(s)), ...goalIds];
  const state = new Map<string, 1 | 2>();
  const post: string[] = [];
  for (const root of roots) {
    if (state.has(root)) continue;
    const stack: [string, number][] = [[root, 0]];
    state.set(root, 1);
    while (stack.length > 0) {
      const top = stack[stack.length - 1]!;
      const edges = out.get(top[0]) ?? [];
      if (top[1] < edges.length) {
        const next = edges[top[1]]!.target;
        top[1] += 1;
        if (!state.has(next)) {
          state.set(next, 1);
          stack.push([next, 0]);
        }
      } else {
        state.set(top[0], 2);
        post.push(top[0]);
        stack.pop();
      }
    }
  }
  const order = post.reverse();
  const position = new Map(order.map((id, i) => [id, i]));
  const layer = new Map<string, number>(order.map((id) => [id, 0]));
  for (const id of order) {
    for (const { target } of out.get(id) ?? []) {
      // Only forward edges (in topological order) push a goal right; back edges close loops.
      if ((position.get(target) ?? 0) > (position.get(id) ?? 0)) {
        layer.set(target, Math.max(layer.get(target) ?? 0, (layer.get(id) ?? 0) + 1));
      }
    }
  }
  const last = Math.max(0, ...layer.values()) + (goalIds.length > 0 ? 1 : 0);
  const columns: string[][] = [];
  for (const id of order) (columns[layer.get(id) ?? 0] ??= []).push(id);
  // Wrapped (`aspect` given): bands of columns, one below the other, so that a long chain
  // reads like lines of text at about that aspect ratio instead of one thin strip.
  const dx = GOAL_SIZE.width + 90;
  const dy = GOAL_SIZE.height + 40;
  const height = Math.max(1, ...columns.map((c) => c.length));
  const bandGap = height * dy + 60;
  const bandWidth = aspect ? Math.max(2, Math.ceil(Math.sqrt(((last + 1) * aspect * bandGap) / dx))) : Infinity;
  const place = (column: number, y: number) =>
    aspect ? { x: (column % bandWidth) * dx, y: Math.floor(column / bandWidth) * bandGap + y } : { x: column * dx, y };
  const row = new Map<string, number>();
  const incoming = new Map<string, number[]>();
  const layout: Layout = {};
  columns.forEach((column, x) => {
    const weight = (id: string) => {
      const ys = incoming.get(id);
      return ys && ys.length > 0 ? ys.reduce((a, b) => a + b, 0) / ys.length : Number.MAX_SAFE_INTEGER;
    };
    const sorted = x === 0 ? column : [...column].sort((a, b) => weight(a) - weight(b));
    sorted.forEach((id, y) => {
      row.set(id, y);
      layout[id] = place(x, y * dy);
      for (const { target, rank } of out.get(id) ?? []) {
        (incoming.get(target) ?? incoming.set(target, []).get(target)!).push(y + rank);
      }
    });
  });
  terminals(orders).forEach((t, i) => {
    if (!layout[t.id]) layout[t.id] = place(last, i * (TERMINAL_SIZE.height + 60));
  });
  return layout;
}

/** ELK lays out orders up to this many goals; larger ones get the linear layered layout. ELK
 * crosses fewer edges on Pirates (49 goals) and 100 goals (crossings.test.ts), but its layouts
 * of them are larger: Pirates' ids clashed at its fit (test_editor_screen.py), the 100-goal one
 * did not fit a 1024 px canvas at the least zoom (test_editor_canvas.py); and it takes 2-10 s
 * on a loaded machine. */
export const ELK_MAX_GOALS = 40;

let elk: InstanceType<typeof ELK> | null = null;

/** ELK's layered layout of the orders: goals with an input port (west) and three output ports
 * (east, in outcome order), terminals with an input port; edges to unknown targets left out. */
export async function elkLayout(orders: Orders, sizes: Sizes = {}, aspect?: number): Promise<Layout> {
  const ids = new Set<string>();
  const children: ElkNode[] = [];
  const size = (id: string, fallback: { width: number; height: number }) => sizes[id] ?? fallback;
  for (const g of goals(orders)) {
    if (ids.has(g.id)) continue;
    ids.add(g.id);
    children.push({
      id: g.id,
      ...size(g.id, GOAL_SIZE),
      layoutOptions: { "elk.portConstraints": "FIXED_ORDER" },
      ports: [
        // Clockwise from the top left: the east side's ports top to bottom, then the west's.
        ...OUTCOMES.map((o, i) => ({ id: `${g.id}\u0000${o}`, width: 1, height: 1, layoutOptions: { "elk.port.side": "EAST", "elk.port.index": String(i) } })),
        { id: `${g.id}\u0000in`, width: 1, height: 1, layoutOptions: { "elk.port.side": "WEST", "elk.port.index": "3" } },
      ],
    });
  }
  for (const t of terminals(orders)) {
    if (ids.has(t.id)) continue;
    ids.add(t.id);
    children.push({ id: t.id, ...size(t.id, TERMINAL_SIZE), ports: [{ id: `${t.id}\u0000in`, width: 1, height: 1, layoutOptions: { "elk.port.side": "WEST" } }] });
  }
  const edges: ElkExtendedEdge[] = [];
  for (const g of goals(orders)) {
    for (const o of OUTCOMES) {
      for (const target of successors(g, o)) {
        if (ids.has(target)) edges.push({ id: `${g.id}\u0000${o}\u0000${target}\u0000${edges.length}`, sources: [`${g.id}\u0000${o}`], targets: [`${target}\u0000in`] });
      }
    }
  }
  const wrap = aspect !== undefined;
  elk ??= new ELK();
  const graph = await elk.layout({
    id: "root",
    children,
    edges,
    layoutOptions: {
      "elk.algorithm": "layered",
      "elk.direction": "RIGHT",
      // Far out an id may take two lines below its node (editor.css): room for them at the
      // least zoom (2 x 1.05 x 11.5 px / 0.15 is about 161 units, the node 112 tall).
      "elk.spacing.nodeNode": "56",
      "elk.layered.spacing.nodeNodeBetweenLayers": "70",
      "elk.layered.crossingMinimization.strategy": "LAYER_SWEEP",
      // Long chains read like lines of text, at about the canvas's aspect ratio.
      ...(wrap ? { "elk.layered.wrapping.strategy": "MULTI_EDGE", "elk.aspectRatio": String(aspect) } : {}),
    },
  });
  const layout: Layout = {};
  for (const n of graph.children ?? []) layout[n.id] = { x: Math.round(n.x ?? 0), y: Math.round(n.y ?? 0) };
  return layout;
}

/** Lays the orders out: ELK up to ELK_MAX_GOALS goals, else the linear layered layout. */
export function autoLayout(orders: Orders, sizes: Sizes = {}, aspect?: number): Promise<Layout> {
  if (goals(orders).length <= ELK_MAX_GOALS) return elkLayout(orders, sizes, aspect);
  return Promise.resolve(layeredLayout(orders, aspect));
}
