/**
 * Auto-layout adapter: orders -> an ELK graph (layered, left to right, each goal's outcome
 * ports in the fixed order succeed, fail, violate top to bottom, so the three branches of a
 * goal do not cross needlessly) and the ELK result -> the draft's layout.
 */
import type { ElkNode } from "elkjs/lib/elk-api";

import { goals, type Layout, type Orders, OUTCOMES, successors, terminals } from "./graph";

export const GOAL_SIZE = { width: 220, height: 96 };
export const TERMINAL_SIZE = { width: 160, height: 72 };

export const LAYOUT_OPTIONS: Record<string, string> = {
  "elk.algorithm": "layered",
  "elk.direction": "RIGHT",
  "elk.layered.spacing.nodeNodeBetweenLayers": "90",
  "elk.spacing.nodeNode": "40",
  // Edges into one terminal share their route (far fewer dummy nodes on large orders).
  "elk.layered.mergeEdges": "true",
};

export function portId(node: string, port: string): string {
  return `${node}.${port}`;
}

/** Rendered sizes of nodes (React Flow's measurements), when known: ELK then leaves room for them. */
export type Sizes = Record<string, { width: number; height: number }>;

/** Long chains wrap into rows of about this width : height (ELK's layered wrapping). */
export function wrapOptions(aspect: number | undefined): Record<string, string> {
  if (!aspect) return {};
  return {
    "elk.layered.wrapping.strategy": "MULTI_EDGE",
    "elk.aspectRatio": aspect.toFixed(2),
    "elk.layered.wrapping.additionalEdgeSpacing": "20",
  };
}

export function toElkGraph(orders: Orders, sizes: Sizes = {}, aspect?: number): ElkNode {
  const ids = new Set<string>();
  const children: ElkNode[] = [];
  for (const g of goals(orders)) {
    if (ids.has(g.id)) continue;
    ids.add(g.id);
    children.push({
      id: g.id,
      ...GOAL_SIZE,
      ...sizes[g.id],
      layoutOptions: { "elk.portConstraints": "FIXED_ORDER" },
      ports: [
        { id: portId(g.id, "in"), width: 1, height: 1, layoutOptions: { "elk.port.side": "WEST", "elk.port.index": "0" } },
        ...OUTCOMES.map((o, i) => ({
          id: portId(g.id, o),
          width: 1,
          height: 1,
          layoutOptions: { "elk.port.side": "EAST", "elk.port.index": String(i) },
        })),
      ],
    });
  }
  for (const t of terminals(orders)) {
    if (ids.has(t.id)) continue;
    ids.add(t.id);
    children.push({
      id: t.id,
      ...TERMINAL_SIZE,
      ...sizes[t.id],
      layoutOptions: { "elk.portConstraints": "FIXED_SIDE" },
      ports: [{ id: portId(t.id, "in"), width: 1, height: 1, layoutOptions: { "elk.port.side": "WEST" } }],
    });
  }
  const edges: NonNullable<ElkNode["edges"]> = [];
  for (const g of goals(orders)) {
    for (const o of OUTCOMES) {
      for (const target of successors(g, o)) {
        if (!ids.has(target)) continue; // a dangling target is a finding, not a layout edge
        edges.push({ id: `${g.id}:${o}:${target}`, sources: [portId(g.id, o)], targets: [portId(target, "in")] });
      }
    }
  }
  return { id: "root", layoutOptions: { ...LAYOUT_OPTIONS, ...wrapOptions(aspect) }, children, edges };
}

/** The positions ELK computed, keyed by node id (top-left corners, as React Flow wants). */
export function fromElkGraph(result: ElkNode): Layout {
  const layout: Layout = {};
  for (const child of result.children ?? []) {
    layout[child.id] = { x: Math.round(child.x ?? 0), y: Math.round(child.y ?? 0) };
  }
  return layout;
}

/** Above this many goals ELK's layered layout takes seconds; a linear-time one is used. */
export const ELK_MAX_GOALS = 60;

/**
 * A linear-time layered layout for large orders: goals in columns by their longest distance
 * from the start (back edges of loops ignored), terminals in the last column, and inside a
 * column ordered by the mean position of their predecessors' outcome ports (s above f above c).
 */
export function fastLayout(orders: Orders, aspect?: number): Layout {
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

/** Lays the orders out: ELK (loaded on first use, a large module) or, for large orders, fastLayout. */
export async function autoLayout(orders: Orders, sizes: Sizes = {}, aspect?: number): Promise<Layout> {
  if (goals(orders).length > ELK_MAX_GOALS) return fastLayout(orders, aspect);
  const { default: ELK } = await import("elkjs/lib/elk.bundled.js");
  const elk = new ELK();
  return fromElkGraph(await elk.layout(toElkGraph(orders, sizes, aspect)));
}
