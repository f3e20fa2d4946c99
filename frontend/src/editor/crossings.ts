/**
 * Edge crossings of a layout, to compare layouts (crossings.test.ts). Each outcome edge is taken
 * as the straight segment from its outcome handle (the node's right side, s/f/c at a quarter,
 * half and three quarters of its height) to the target's input handle (left side, middle); the
 * canvas draws curves between the same points, so the count is an estimate of what a person sees.
 */
import { goals, type Layout, type Orders, OUTCOMES, successors } from "./graph";
import { GOAL_SIZE, TERMINAL_SIZE } from "./layout";

interface Segment {
  source: string;
  target: string;
  a: { x: number; y: number };
  b: { x: number; y: number };
}

function cross(o: { x: number; y: number }, p: { x: number; y: number }, q: { x: number; y: number }): number {
  return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x);
}

function intersects(s: Segment, t: Segment): boolean {
  // Edges that share an end meet there: that is not a crossing.
  if (s.source === t.source || s.target === t.target || s.source === t.target || s.target === t.source) return false;
  const d1 = cross(t.a, t.b, s.a);
  const d2 = cross(t.a, t.b, s.b);
  const d3 = cross(s.a, s.b, t.a);
  const d4 = cross(s.a, s.b, t.b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

export function edgeSegments(orders: Orders, layout: Layout): Segment[] {
  const isGoal = new Set(goals(orders).map((g) => g.id));
  const segments: Segment[] = [];
  for (const g of goals(orders)) {
    const from = layout[g.id];
    if (!from) continue;
    OUTCOMES.forEach((o, i) => {
      for (const target of successors(g, o)) {
        const to = layout[target];
        if (!to) continue;
        const height = isGoal.has(target) ? GOAL_SIZE.height : TERMINAL_SIZE.height;
        segments.push({
          source: g.id,
          target,
          a: { x: from.x + GOAL_SIZE.width, y: from.y + (GOAL_SIZE.height * (i + 1)) / 4 },
          b: { x: to.x, y: to.y + height / 2 },
        });
      }
    });
  }
  return segments;
}

/** How many pairs of outcome edges cross (quadratic in the edges: fine for a few hundred). */
export function countCrossings(orders: Orders, layout: Layout): number {
  const segments = edgeSegments(orders, layout);
  let count = 0;
  for (let i = 0; i < segments.length; i += 1) {
    for (let j = i + 1; j < segments.length; j += 1) if (intersects(segments[i]!, segments[j]!)) count += 1;
  }
  return count;
}
