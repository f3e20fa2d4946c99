/**
 * Auto layout: a layered layout, left to right, goals in columns by their longest distance from
 * the start, each goal's successors ordered by its outcome ports (succeed, fail, violate top to
 * bottom, so the three branches of a goal do not cross needlessly), long chains wrapped into
 * bands at the canvas's aspect ratio. Linear time: it runs on every open and every "Auto
 * layout" (in a worker, layoutClient.ts).
 *
 * ELK (elkjs layered with port constraints) was used for up to 60 goals until issue 18: on this
 * project's machines it took 0.5-2 s for the 5-goal exemplar and 2-8 s for the 49-goal Pirates
 * mission, and its wrapped Pirates layout (about 3970 x 3320) could not be fitted to a 1024 px
 * canvas at a legible zoom; this layout takes about 1 ms for Pirates (3010 x 1780).
 */
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

/** Lays the orders out (asynchronous, as the worker's protocol is; `sizes` is accepted for it). */
export function autoLayout(orders: Orders, _sizes: Sizes = {}, aspect?: number): Promise<Layout> {
  return Promise.resolve(layeredLayout(orders, aspect));
}
