/**
 * The order of the rehearsal page's goal cards: the order a mission is flown
 * in, not the order a breadth-first search meets goals (which put G6 before G3). Every goal comes
 * after each goal that can lead to it (a topological order, Kahn's algorithm), and among the
 * goals that could come next the one a depth-first walk over succeed, fail, violate meets first
 * wins, so the succeed path reads first (G1, G2, G3, G4, G5 for the exemplar). Goals on a loop
 * (which validation reports) follow in that walk's order; unreachable goals come last, in file
 * order.
 */
import { goals, OUTCOMES, type Orders, startIds, successors } from "../editor/graph";

export function pathOrder(orders: Orders): string[] {
  const all = goals(orders);
  const byId = new Map(all.map((g) => [g.id, g]));
  const nextOf = (id: string): string[] => {
    const goal = byId.get(id);
    return goal ? [...new Set(OUTCOMES.flatMap((o) => successors(goal, o)))].filter((t) => byId.has(t)) : [];
  };
  // Depth-first preorder from the start, iterative so that a long chain cannot overflow the stack.
  const rank = new Map<string, number>();
  for (const start of startIds(orders)) {
    const stack = byId.has(start) ? [start] : [];
    while (stack.length) {
      const id = stack.pop()!;
      if (rank.has(id)) continue;
      rank.set(id, rank.size);
      stack.push(...nextOf(id).reverse());
    }
  }
  const reached = [...rank.keys()];
  const waiting = new Map(reached.map((id) => [id, 0]));
  for (const id of reached) for (const t of nextOf(id)) waiting.set(t, (waiting.get(t) ?? 0) + 1);
  // Ready goals, kept sorted by rank (binary insertion).
  const ready: string[] = reached.filter((id) => waiting.get(id) === 0);
  const insert = (id: string) => {
    let lo = 0;
    let hi = ready.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (rank.get(ready[mid]!)! < rank.get(id)!) lo = mid + 1;
      else hi = mid;
    }
    ready.splice(lo, 0, id);
  };
  const order: string[] = [];
  const placed = new Set<string>();
  while (ready.length) {
    const id = ready.shift()!;
    order.push(id);
    placed.add(id);
    for (const t of nextOf(id)) {
      const left = waiting.get(t)! - 1;
      waiting.set(t, left);
      if (left === 0) insert(t);
    }
  }
  for (const id of reached) if (!placed.has(id)) order.push(id);
  for (const g of all) if (!rank.has(g.id)) order.push(g.id);
  return order;
}

/** The outcome a key press chooses (the Figure 6 prompt's s, f, c), or null. */
export function outcomeKey(key: string): "succeed" | "fail" | "violate" | null {
  switch (key.toLowerCase()) {
    case "s":
      return "succeed";
    case "f":
      return "fail";
    case "c":
      return "violate";
    default:
      return null;
  }
}

/** A flat goal id's place: its top-level goal and its id without unrolling marks
 * (`G1/G1.2#3` -> G1, G1/G1.2). */
export function stepPlace(id: string): { top: string; full: string } {
  const full = id.replace(/[#@][^/]*/g, "");
  return { top: full.split("/")[0] ?? full, full };
}
