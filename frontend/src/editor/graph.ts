/**
 * Pure graph-editing logic of the mission editor: orders (countersign.orders/1) to nodes and
 * edges and back, connection rules, edits. No React here; everything returns new objects.
 */
import type { Schema } from "../api/client";
import type { components } from "../api/schema";

export const OUTCOMES = ["succeed", "fail", "violate"] as const;
export type Outcome = (typeof OUTCOMES)[number];

export const OUTCOME_LETTER: Record<Outcome, string> = { succeed: "s", fail: "f", violate: "c" };
export const OUTCOME_LABEL: Record<Outcome, string> = {
  succeed: "Succeed",
  fail: "Fail",
  violate: "Violate (constraint)",
};

// The orders' types are the server's (generated from its Pydantic model via OpenAPI), so the
// editor cannot drift from what the API accepts, and as answers read them (openapi-fetch's
// `Readable`: a pair is an array, read through api/pair.ts), so an answer's orders need no cast.
type Schemas = components["schemas"];
export type GoalSpec = Schema<"Goal">;
export type TerminalSpec = Schema<"Terminal">;
export type ConstraintSpec = Schema<"Constraint">;
export type Orders = Schema<"Orders">;

export interface Point {
  x: number;
  y: number;
}
/** The draft's `layout`: node id -> position (editor-only, outside the orders). */
export type Layout = Schemas["Layout"];

export const DEFAULT_TERMINALS: TerminalSpec[] = [
  { id: "COMPLETE", kind: "complete", title: "Mission complete" },
  { id: "ABORT", kind: "abort", title: "Mission abort" },
];

export function goals(orders: Orders): GoalSpec[] {
  return orders.goals ?? [];
}
export function terminals(orders: Orders): TerminalSpec[] {
  return orders.terminals ?? DEFAULT_TERMINALS;
}
export function startIds(orders: Orders): string[] {
  const s = orders.start;
  return s == null ? [] : Array.isArray(s) ? s : [s];
}

/** Successor targets named for an outcome (a list only comes from Turtle/AVCL input). */
export function successors(goal: GoalSpec, outcome: Outcome): string[] {
  const t = goal.next?.[outcome];
  return t == null ? [] : Array.isArray(t) ? t : [t];
}

export interface GraphNode {
  id: string;
  kind: "goal" | "terminal";
  label: string;
  position: Point;
  start: boolean;
  terminalKind?: "complete" | "abort";
}
export interface GraphEdge {
  id: string;
  source: string;
  outcome: Outcome;
  target: string;
  /** The target names neither a goal nor a terminal. */
  dangling: boolean;
}

export function edgeId(source: string, outcome: Outcome, target: string): string {
  return `${source}:${outcome}:${target}`;
}

/** Orders and layout -> the nodes and edges of the canvas (nodes without a position get one). */
export function ordersToGraph(orders: Orders, layout: Layout): { nodes: GraphNode[]; edges: GraphEdge[] } {
  const starts = new Set(startIds(orders));
  const nodes: GraphNode[] = [];
  const ids = new Set<string>();
  goals(orders).forEach((g, i) => {
    ids.add(g.id);
    nodes.push({
      id: g.id,
      kind: "goal",
      label: g.title || g.id,
      position: layout[g.id] ?? { x: 0, y: i * 130 },
      start: starts.has(g.id),
    });
  });
  terminals(orders).forEach((t, i) => {
    ids.add(t.id);
    nodes.push({
      id: t.id,
      kind: "terminal",
      label: t.title || t.id,
      position: layout[t.id] ?? { x: 320, y: i * 100 },
      start: false,
      terminalKind: t.kind,
    });
  });
  const edges: GraphEdge[] = [];
  for (const g of goals(orders)) {
    for (const outcome of OUTCOMES) {
      for (const target of successors(g, outcome)) {
        edges.push({ id: edgeId(g.id, outcome, target), source: g.id, outcome, target, dangling: !ids.has(target) });
      }
    }
  }
  return { nodes, edges };
}

export interface ConnectionCheck {
  ok: boolean;
  reason?: string;
}

/** Whether `source` may get `target` as its successor for `outcome` (checked while dragging). */
export function checkConnection(
  orders: Orders,
  source: string | null | undefined,
  outcome: string | null | undefined,
  target: string | null | undefined,
): ConnectionCheck {
  const goal = goals(orders).find((g) => g.id === source);
  if (!goal) return { ok: false, reason: "Connections start at a goal's outcome." };
  if (!OUTCOMES.includes(outcome as Outcome)) return { ok: false, reason: "Pick an outcome handle (s, f or c)." };
  const known = goals(orders).some((g) => g.id === target) || terminals(orders).some((t) => t.id === target);
  if (!target || !known) return { ok: false, reason: "Connect to a goal or a terminal." };
  if (successors(goal, outcome as Outcome).length > 0) {
    return { ok: false, reason: `${goal.id} already has a successor for ${outcome}; delete that edge first.` };
  }
  return { ok: true };
}

function mapGoal(orders: Orders, id: string, change: (g: GoalSpec) => GoalSpec): Orders {
  return { ...orders, goals: goals(orders).map((g) => (g.id === id ? change(g) : g)) };
}

/** Sets (or with null clears) the successor of one outcome. */
export function setSuccessor(orders: Orders, source: string, outcome: Outcome, target: string | null): Orders {
  return mapGoal(orders, source, (g) => {
    const next = { ...(g.next ?? {}) };
    if (target) next[outcome] = target;
    else delete next[outcome];
    return { ...g, next };
  });
}

/** Connects when the rule allows it; otherwise returns the orders unchanged and the reason. */
export function connect(
  orders: Orders,
  source: string,
  outcome: string,
  target: string,
): { orders: Orders; check: ConnectionCheck } {
  const check = checkConnection(orders, source, outcome, target);
  return { orders: check.ok ? setSuccessor(orders, source, outcome as Outcome, target) : orders, check };
}

/** Removes one edge (one target of one outcome). */
export function disconnect(orders: Orders, source: string, outcome: Outcome, target: string): Orders {
  return mapGoal(orders, source, (g) => {
    const rest = successors(g, outcome).filter((t) => t !== target);
    const next = { ...(g.next ?? {}) };
    if (rest.length === 0) delete next[outcome];
    else next[outcome] = rest.length === 1 ? rest[0]! : rest;
    return { ...g, next };
  });
}

/** The first free id of the form PREFIX<n>. */
export function nextId(orders: Orders, prefix: string): string {
  const used = new Set<string>([
    ...goals(orders).map((g) => g.id),
    ...terminals(orders).map((t) => t.id),
    ...(orders.constraints ?? []).map((c) => c.id),
  ]);
  let n = 1;
  while (used.has(`${prefix}${n}`)) n += 1;
  return `${prefix}${n}`;
}

/** Adds a goal; the first goal of a mission becomes its start. */
export function addGoal(orders: Orders, title = ""): { orders: Orders; id: string } {
  const id = nextId(orders, "G");
  const goal: GoalSpec = { id, title: title || `Goal ${id}`, next: {} };
  const updated: Orders = { ...orders, goals: [...goals(orders), goal] };
  if (startIds(orders).length === 0) updated.start = id;
  return { orders: updated, id };
}

export function addTerminal(orders: Orders, kind: "complete" | "abort"): { orders: Orders; id: string } {
  const base = kind === "complete" ? "COMPLETE" : "ABORT";
  const taken = new Set([...goals(orders).map((g) => g.id), ...terminals(orders).map((t) => t.id)]);
  let id = base;
  for (let n = 2; taken.has(id); n += 1) id = `${base}${n}`;
  const terminal: TerminalSpec = { id, kind, title: kind === "complete" ? "Mission complete" : "Mission abort" };
  return { orders: { ...orders, terminals: [...terminals(orders), terminal] }, id };
}

/** Deletes goals and terminals, the edges into them, and their mentions in constraint scopes. */
export function deleteNodes(orders: Orders, ids: Iterable<string>): Orders {
  const gone = new Set(ids);
  if (gone.size === 0) return orders;
  const kept = goals(orders)
    .filter((g) => !gone.has(g.id))
    .map((g) => {
      const next: GoalSpec["next"] = {};
      for (const outcome of OUTCOMES) {
        const rest = successors(g, outcome).filter((t) => !gone.has(t));
        if (rest.length > 0) next[outcome] = rest.length === 1 ? rest[0]! : rest;
      }
      return { ...g, next };
    });
  const updated: Orders = { ...orders, goals: kept };
  if (terminals(orders).some((t) => gone.has(t.id))) {
    updated.terminals = terminals(orders).filter((t) => !gone.has(t.id));
  }
  if (orders.constraints) {
    updated.constraints = orders.constraints.map((c) =>
      Array.isArray(c.applies_to) ? { ...c, applies_to: c.applies_to.filter((g) => !gone.has(g)) } : c,
    );
  }
  const starts = startIds(orders).filter((s) => !gone.has(s));
  if (starts.length !== startIds(orders).length) {
    updated.start = starts.length === 0 ? kept[0]?.id ?? null : starts.length === 1 ? starts[0] : starts;
  }
  return updated;
}

export function updateGoal(orders: Orders, id: string, patch: Partial<GoalSpec>): Orders {
  return mapGoal(orders, id, (g) => {
    const updated: GoalSpec = { ...g, ...patch };
    for (const [key, value] of Object.entries(patch)) {
      if (value === undefined) delete updated[key];
    }
    return updated;
  });
}

export function updateTerminal(orders: Orders, id: string, patch: Partial<TerminalSpec>): Orders {
  return { ...orders, terminals: terminals(orders).map((t) => (t.id === id ? { ...t, ...patch } : t)) };
}

export function addConstraint(orders: Orders): { orders: Orders; id: string } {
  const id = nextId(orders, "C");
  const constraint: ConstraintSpec = { id, text: "", applies_to: "mission" };
  return { orders: { ...orders, constraints: [...(orders.constraints ?? []), constraint] }, id };
}

export function updateConstraint(orders: Orders, id: string, patch: Partial<ConstraintSpec>): Orders {
  return {
    ...orders,
    constraints: (orders.constraints ?? []).map((c) => {
      if (c.id !== id) return c;
      const updated: ConstraintSpec = { ...c, ...patch };
      if (patch.expr === "") delete updated.expr;
      return updated;
    }),
  };
}

export function deleteConstraint(orders: Orders, id: string): Orders {
  return { ...orders, constraints: (orders.constraints ?? []).filter((c) => c.id !== id) };
}

/** Toggles one goal in a constraint's scope; an emptied list stays a list (C2 reports it). */
export function toggleScope(orders: Orders, id: string, goal: string): Orders {
  const c = (orders.constraints ?? []).find((x) => x.id === id);
  if (!c) return orders;
  const list = Array.isArray(c.applies_to) ? c.applies_to : [];
  const applies = list.includes(goal) ? list.filter((g) => g !== goal) : [...list, goal];
  return updateConstraint(orders, id, { applies_to: applies });
}

/** Envelope <-> text lines "quantity min max". */
export function envelopeToText(envelope: GoalSpec["envelope"]): string {
  return Object.entries(envelope ?? {})
    .map(([q, [lo, hi]]) => `${q} ${lo} ${hi}`)
    .join("\n");
}
export function parseEnvelope(text: string): { envelope?: Record<string, [number, number]>; error?: string } {
  const envelope: Record<string, [number, number]> = {};
  const lines = text.split("\n").map((l) => l.trim()).filter(Boolean);
  for (const [i, line] of lines.entries()) {
    const parts = line.split(/[\s,]+/);
    const [q, lo, hi] = parts;
    const low = Number(lo);
    const high = Number(hi);
    if (parts.length !== 3 || !q || !Number.isFinite(low) || !Number.isFinite(high)) {
      return { error: `Line ${i + 1}: write "quantity min max", e.g. "depth_m 25 50".` };
    }
    if (low > high) return { error: `Line ${i + 1}: the lower bound ${low} is above the upper bound ${high}.` };
    envelope[q] = [low, high];
  }
  return { envelope };
}

/** Node ids named by findings -> the findings' codes and worst severity. */
export function markersBySubject(
  findings: { code: string; severity: string; subjects: string[] }[],
): Map<string, { codes: string[]; severity: "error" | "warning" }> {
  const markers = new Map<string, { codes: string[]; severity: "error" | "warning" }>();
  for (const f of findings) {
    for (const subject of f.subjects) {
      const m = markers.get(subject) ?? { codes: [], severity: "warning" as const };
      if (!m.codes.includes(f.code)) m.codes.push(f.code);
      if (f.severity === "error") m.severity = "error";
      markers.set(subject, m);
    }
  }
  return markers;
}

/** Plain-language differences between two versions of the orders (for the conflict dialog). */
export function describeDifferences(mine: Orders, theirs: Orders): string[] {
  const out: string[] = [];
  if ((mine.title ?? "") !== (theirs.title ?? "")) out.push(`Title: yours "${mine.title ?? ""}", theirs "${theirs.title ?? ""}".`);
  if (JSON.stringify(startIds(mine)) !== JSON.stringify(startIds(theirs))) {
    out.push(`Start: yours ${startIds(mine).join(", ") || "none"}, theirs ${startIds(theirs).join(", ") || "none"}.`);
  }
  const lists: [string, { id: string }[], { id: string }[]][] = [
    ["Goal", goals(mine), goals(theirs)],
    ["Terminal", terminals(mine), terminals(theirs)],
    ["Constraint", mine.constraints ?? [], theirs.constraints ?? []],
  ];
  for (const [what, a, b] of lists) {
    const byId = new Map(b.map((x) => [x.id, x]));
    for (const x of a) {
      const other = byId.get(x.id);
      if (!other) out.push(`${what} ${x.id}: only in yours.`);
      else if (stable(x) !== stable(other)) out.push(`${what} ${x.id}: differs.`);
    }
    const mineIds = new Set(a.map((x) => x.id));
    for (const x of b) if (!mineIds.has(x.id)) out.push(`${what} ${x.id}: only in theirs.`);
  }
  const known = new Set(["title", "start", "goals", "terminals", "constraints"]);
  for (const key of new Set([...Object.keys(mine), ...Object.keys(theirs)])) {
    if (!known.has(key) && stable(mine[key]) !== stable(theirs[key])) out.push(`Field "${key}" differs.`);
  }
  return out;
}

/** JSON with sorted keys, for comparisons. */
export function stable(value: unknown): string {
  return JSON.stringify(value, (_k, v: unknown) =>
    v && typeof v === "object" && !Array.isArray(v)
      ? Object.fromEntries(Object.entries(v as Record<string, unknown>).sort(([a], [b]) => (a < b ? -1 : a > b ? 1 : 0)))
      : v,
  );
}

/** A path as the API reports it (paths list, BUDGET and PROPERTY counterexamples). */
export interface PathLike {
  goals: string[];
  outcomes: string[];
  terminal: string | null;
}

/** The counterexample path a BUDGET or PROPERTY finding carries, if any. */
export function findingPath(finding: Record<string, unknown>): PathLike | null {
  const holder = (finding.path && typeof finding.path === "object" ? finding.path : finding) as Record<string, unknown>;
  const g = holder.goals;
  const o = holder.outcomes;
  if (!Array.isArray(g) || !Array.isArray(o) || g.length !== o.length || g.length === 0) return null;
  return { goals: g as string[], outcomes: o as string[], terminal: (holder.terminal as string | null | undefined) ?? null };
}

/** The edge ids and node ids a path runs through. */
export function pathElements(path: PathLike): { edges: Set<string>; nodes: Set<string> } {
  const edges = new Set<string>();
  const nodes = new Set<string>(path.goals);
  if (path.terminal) nodes.add(path.terminal);
  path.goals.forEach((g, i) => {
    const to = path.goals[i + 1] ?? path.terminal;
    const outcome = path.outcomes[i];
    if (to && outcome) edges.add(edgeId(g, outcome as Outcome, to));
  });
  return { edges, nodes };
}

/**
 * Edges that findings name: the edges of a loop (G7: both ends in the cycle), and the edges of
 * counterexample paths (BUDGET, PROPERTY). Edge id -> codes.
 */
export function edgeMarkers(
  findings: { code: string; severity: string; subjects: string[] }[],
  edges: { id: string; source: string; target: string }[],
): Map<string, { codes: string[]; severity: "error" | "warning" }> {
  const marks = new Map<string, { codes: string[]; severity: "error" | "warning" }>();
  const add = (id: string, code: string, severity: string) => {
    const m = marks.get(id) ?? { codes: [], severity: "warning" as const };
    if (!m.codes.includes(code)) m.codes.push(code);
    if (severity === "error") m.severity = "error";
    marks.set(id, m);
  };
  for (const f of findings) {
    if (f.code === "G7") {
      const cycle = new Set(f.subjects);
      for (const e of edges) if (cycle.has(e.source) && cycle.has(e.target)) add(e.id, f.code, f.severity);
    } else {
      const path = findingPath(f);
      if (path) for (const id of pathElements(path).edges) add(id, f.code, f.severity);
    }
  }
  return marks;
}
