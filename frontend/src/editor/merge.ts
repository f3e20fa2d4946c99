/**
 * Three-way merge of concurrent edits of one draft. `base` is the orders both
 * sides started from (the revision last read or saved), `mine` the editor's, `theirs` the one
 * saved meanwhile. Changes to different items (goals, terminals, constraints, norms, areas, ...)
 * and to different fields of one item merge by themselves, recursively into plain objects (a
 * goal's `next` per outcome, an envelope per quantity); lists and scalars are atomic. Where both
 * sides changed the same field differently, or one deleted what the other changed, the item is a
 * conflict: shown side by side, resolved by a choice per item (`resolveMerge`). Pure.
 */
import { DEFAULT_TERMINALS, type Orders, stable } from "./graph";

/** Top-level lists of items with an `id`, merged item by item. */
const ID_LISTS: Record<string, string> = {
  goals: "Goal",
  terminals: "Terminal",
  constraints: "Constraint",
  norms: "Norm",
  areas: "Area",
  vehicles: "Vehicle",
  properties: "Property",
  charts: "Chart",
};
/** Top-level records merged key by key (each key an item). */
const RECORDS: Record<string, string> = { quantities: "Quantity" };

export interface MergeConflict {
  /** Unique within one merge: `goals:G2`, `quantities:depth_m`, `field:title`. */
  key: string;
  /** What the operator reads: "Goal G2", "Mission field title". */
  label: string;
  base: unknown;
  mine: unknown;
  theirs: unknown;
  /** The fields both sides changed differently (empty when one side deleted the item). */
  fields: string[];
}

export interface MergeResult {
  /** The merged orders; each conflict holds theirs until resolved. */
  orders: Orders;
  /** What merged by itself, in words ("Goal G3: their change kept"). */
  merged: string[];
  conflicts: MergeConflict[];
}

export type Side = "mine" | "theirs";

type Json = Record<string, unknown>;
const ABSENT = undefined;

function same(a: unknown, b: unknown): boolean {
  return a === b || stable(a) === stable(b);
}
function isPlainObject(v: unknown): v is Json {
  return typeof v === "object" && v !== null && !Array.isArray(v);
}

/** Merges one value; `conflicts` collects the dotted paths both sides changed differently. */
function mergeValue(base: unknown, mine: unknown, theirs: unknown, path: string, conflicts: string[]): unknown {
  if (same(mine, theirs)) return mine;
  if (same(mine, base)) return theirs;
  if (same(theirs, base)) return mine;
  if (isPlainObject(mine) && isPlainObject(theirs)) {
    const b = isPlainObject(base) ? base : {};
    const out: Json = {};
    for (const key of new Set([...Object.keys(theirs), ...Object.keys(mine)])) {
      const v = mergeValue(b[key], mine[key], theirs[key], path ? `${path}.${key}` : key, conflicts);
      if (v !== ABSENT) out[key] = v;
    }
    return out;
  }
  conflicts.push(path);
  return theirs;
}

interface ItemOutcome {
  value: unknown;
  note?: string;
  conflict?: MergeConflict;
}

/** Merges one item (absent = undefined on a side). */
function mergeItem(key: string, label: string, base: unknown, mine: unknown, theirs: unknown): ItemOutcome {
  if (same(mine, theirs)) return { value: mine };
  if (same(mine, base)) return { value: theirs, note: `${label}: ${theirs === ABSENT ? "their deletion" : base === ABSENT ? "their addition" : "their change"} kept.` };
  if (same(theirs, base)) return { value: mine, note: `${label}: ${mine === ABSENT ? "your deletion" : base === ABSENT ? "your addition" : "your change"} kept.` };
  if (mine === ABSENT || theirs === ABSENT || !isPlainObject(mine) || !isPlainObject(theirs)) {
    return { value: theirs, conflict: { key, label, base, mine, theirs, fields: [] } };
  }
  const fields: string[] = [];
  const value = mergeValue(base, mine, theirs, "", fields);
  if (fields.length > 0) return { value: theirs, conflict: { key, label, base, mine, theirs, fields } };
  return { value, note: `${label}: your change and theirs merged.` };
}

function itemsById(list: unknown): Map<string, unknown> {
  const out = new Map<string, unknown>();
  if (Array.isArray(list)) for (const x of list) if (isPlainObject(x) && typeof x.id === "string" && !out.has(x.id)) out.set(x.id, x);
  return out;
}

/** Merges a list of items by id: theirs' order, then the items only mine added, in my order. */
function mergeList(listKey: string, what: string, base: unknown, mine: unknown, theirs: unknown, result: MergeResult): unknown {
  if (!Array.isArray(mine) && !Array.isArray(theirs) && !Array.isArray(base)) return mergeScalar(listKey, base, mine, theirs, result);
  // Terminals left out mean the two default ones.
  const fill = (v: unknown) => (listKey === "terminals" && v == null ? DEFAULT_TERMINALS : v);
  const [b, m, t] = [itemsById(fill(base)), itemsById(fill(mine)), itemsById(fill(theirs))];
  const order = [...t.keys(), ...[...m.keys()].filter((id) => !t.has(id))];
  const out: unknown[] = [];
  for (const id of order) {
    const outcome = mergeItem(`${listKey}:${id}`, `${what} ${id}`, b.get(id), m.get(id), t.get(id));
    if (outcome.note) result.merged.push(outcome.note);
    if (outcome.conflict) result.conflicts.push(outcome.conflict);
    if (outcome.value !== ABSENT) out.push(outcome.value);
  }
  return out;
}

function mergeRecord(recordKey: string, what: string, base: unknown, mine: unknown, theirs: unknown, result: MergeResult): unknown {
  const [b, m, t] = [base, mine, theirs].map((v) => (isPlainObject(v) ? v : {})) as [Json, Json, Json];
  const out: Json = {};
  for (const key of new Set([...Object.keys(t), ...Object.keys(m)])) {
    const outcome = mergeItem(`${recordKey}:${key}`, `${what} ${key}`, b[key], m[key], t[key]);
    if (outcome.note) result.merged.push(outcome.note);
    if (outcome.conflict) result.conflicts.push(outcome.conflict);
    if (outcome.value !== ABSENT) out[key] = outcome.value;
  }
  return mine === ABSENT && theirs === ABSENT ? ABSENT : out;
}

function mergeScalar(key: string, base: unknown, mine: unknown, theirs: unknown, result: MergeResult): unknown {
  const outcome = mergeItem(`field:${key}`, `Mission field ${key}`, base, mine, theirs);
  if (outcome.note) result.merged.push(outcome.note);
  if (outcome.conflict) result.conflicts.push(outcome.conflict);
  return outcome.value;
}

export function mergeOrders(base: Orders, mine: Orders, theirs: Orders): MergeResult {
  const result: MergeResult = { orders: { ...theirs }, merged: [], conflicts: [] };
  const b = base as Json;
  const m = mine as Json;
  const t = theirs as Json;
  const out: Json = {};
  for (const key of new Set([...Object.keys(t), ...Object.keys(m), ...Object.keys(b)])) {
    const value =
      key in ID_LISTS
        ? mergeList(key, ID_LISTS[key]!, b[key], m[key], t[key], result)
        : key in RECORDS
          ? mergeRecord(key, RECORDS[key]!, b[key], m[key], t[key], result)
          : mergeScalar(key, b[key], m[key], t[key], result);
    if (value !== ABSENT) out[key] = value;
  }
  // The mission's id never changes; the server refuses orders whose id differs.
  result.orders = { ...out, id: theirs.id } as Orders;
  return result;
}

/** Sets one conflict's item to the chosen side's version (absent: removed). */
function applyChoice(orders: Json, conflict: MergeConflict, side: Side): Json {
  const value = side === "mine" ? conflict.mine : conflict.theirs;
  const [kind, ...rest] = conflict.key.split(":");
  const name = rest.join(":");
  if (kind === "field") {
    const out = { ...orders };
    if (value === ABSENT) delete out[name];
    else out[name] = value;
    return out;
  }
  if (kind && kind in RECORDS) {
    const record = { ...(isPlainObject(orders[kind]) ? (orders[kind] as Json) : {}) };
    if (value === ABSENT) delete record[name];
    else record[name] = value;
    return { ...orders, [kind]: record };
  }
  const list = Array.isArray(orders[kind!]) ? (orders[kind!] as unknown[]) : [];
  const at = list.findIndex((x) => isPlainObject(x) && x.id === name);
  const next = [...list];
  if (value === ABSENT) {
    if (at >= 0) next.splice(at, 1);
  } else if (at >= 0) next[at] = value;
  else next.push(value);
  return { ...orders, [kind!]: next };
}

/** The merged orders with each conflict resolved as chosen (unchosen ones: theirs). */
export function resolveMerge(result: MergeResult, choices: Record<string, Side>): Orders {
  let orders = result.orders as Json;
  for (const c of result.conflicts) orders = applyChoice(orders, c, choices[c.key] ?? "theirs");
  return orders as Orders;
}
