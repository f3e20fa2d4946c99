/**
 * Pure edits of the parts of the orders that are not the graph: mission fields, areas,
 * quantities, the vehicle profile, norms, goal parameters, and copy/paste of goals.
 *
 * The digest of the orders covers exactly the fields the author wrote (RFC 8785 of the orders
 * without unset defaults), so these edits never write a field the author left empty: clearing
 * a text or number removes the key. Feature `fulfills`/`measures` are the one exception (they
 * are always lists, as the exemplar writes them).
 */
import type { Schema } from "../api/client";
import { numberPair } from "../api/pair";
import { type GoalSpec, goals, type Layout, type Orders, OUTCOMES, type Point, successors, terminals } from "./graph";

export type LatLon = [number, number];
/** A point as the orders hold it when read from an answer: openapi-fetch's `Readable` types
 * the schema's pairs as arrays, so readers take it through numberPair (api/pair.ts). */
export type Coordinates = readonly number[];

// The orders' parts as the server's model declares them (generated from OpenAPI); features
// and norms below are as the editor writes them, which the server's types do not quite say.
export type AreaSpec = Schema<"Area">;
export type QuantitySpec = Schema<"Quantity">;
// A feature's lists are always written (as the exemplar writes them); a norm being written
// may not have its context yet; the rest is the server's model. (`Omit` would also drop the
// known keys of a schema that allows others; this keeps them.)
type Without<T, K extends PropertyKey> = { [P in keyof T as P extends K ? never : P]: T[P] };
export type FeatureSpec = Without<Schema<"Feature">, "fulfills" | "measures"> & {
  fulfills: string[];
  measures: string[];
};
export type VehicleSpec = Without<Schema<"Vehicle">, "features"> & { features?: FeatureSpec[] };
export type NormSpec = Without<Schema<"Norm">, "context"> & { context?: string };
export const NORM_KINDS = ["forbidden", "obligated", "permitted"] as const;
export type NormKind = (typeof NORM_KINDS)[number];

/** Sets or (for "", undefined, an empty list or object) removes keys of a plain object. */
export function patch<T extends object>(obj: T, changes: Record<string, unknown>): T {
  const out: Record<string, unknown> = { ...(obj as Record<string, unknown>) };
  for (const [k, v] of Object.entries(changes)) {
    const empty =
      v === undefined ||
      v === "" ||
      (typeof v === "number" && Number.isNaN(v)) ||
      (Array.isArray(v) && v.length === 0) ||
      (v !== null && typeof v === "object" && !Array.isArray(v) && Object.keys(v).length === 0);
    if (empty) delete out[k];
    else out[k] = v;
  }
  return out as T;
}

/** "a, b ,c" -> ["a", "b", "c"]. */
export function parseList(text: string): string[] {
  return text.split(",").map((s) => s.trim()).filter(Boolean);
}
/** A number field's text -> a number, or undefined when empty or not a number. */
export function parseNumber(text: string): number | undefined {
  if (text.trim() === "") return undefined;
  const n = Number(text);
  return Number.isFinite(n) ? n : undefined;
}

// ---- Mission ----

export function updateMission(orders: Orders, changes: Record<string, unknown>): Orders {
  return patch(orders, changes);
}

// ---- Goal parameters: one "name value" per line ----

export function paramsToText(params: unknown): string {
  return Object.entries((params as Record<string, unknown> | undefined) ?? {})
    .map(([k, v]) => `${k} ${typeof v === "string" ? v : JSON.stringify(v)}`)
    .join("\n");
}
export function parseParams(text: string): { params?: Record<string, unknown>; error?: string } {
  const params: Record<string, unknown> = {};
  const lines = text.split("\n").map((l) => l.trim()).filter(Boolean);
  for (const [i, line] of lines.entries()) {
    const m = /^([A-Za-z_][A-Za-z0-9_]*)\s+(.+)$/.exec(line);
    if (!m) return { error: `Line ${i + 1}: write "name value", e.g. "pd 0.8".` };
    const raw = m[2]!.trim();
    let value: unknown = raw;
    try {
      value = JSON.parse(raw);
    } catch {
      value = raw;
    }
    params[m[1]!] = value;
  }
  return { params };
}

// ---- Areas ----

export function areas(orders: Orders): AreaSpec[] {
  return orders.areas ?? [];
}
export function freeId(taken: Iterable<string>, prefix: string): string {
  const used = new Set(taken);
  let n = 1;
  while (used.has(`${prefix}${n}`)) n += 1;
  return `${prefix}${n}`;
}
export function addArea(orders: Orders): { orders: Orders; id: string } {
  const id = freeId(areas(orders).map((a) => a.id), "AREA");
  return { orders: { ...orders, areas: [...areas(orders), { id }] }, id };
}
export function updateArea(orders: Orders, id: string, changes: Record<string, unknown>): Orders {
  return { ...orders, areas: areas(orders).map((a) => (a.id === id ? patch(a, changes) : a)) };
}
export function deleteArea(orders: Orders, id: string): Orders {
  return patch(orders, { areas: areas(orders).filter((a) => a.id !== id) });
}
/** Renames an area and every goal's reference to it; refuses a clash. */
export function renameArea(orders: Orders, id: string, to: string): { orders: Orders; error?: string } {
  if (to === id) return { orders };
  if (!to) return { orders, error: "An area needs an id." };
  if (areas(orders).some((a) => a.id === to)) return { orders, error: `Area ${to} exists already.` };
  return {
    orders: {
      ...orders,
      areas: areas(orders).map((a) => (a.id === id ? { ...a, id: to } : a)),
      goals: goals(orders).map((g) => (g.area === id ? { ...g, area: to } : g)),
    },
  };
}
export function setVertex(orders: Orders, id: string, index: number, value: LatLon): Orders {
  const area = areas(orders).find((a) => a.id === id);
  if (!area) return orders;
  const polygon = [...(area.polygon ?? [])];
  polygon[index] = value;
  return updateArea(orders, id, { polygon });
}
export function addVertex(orders: Orders, id: string, at?: LatLon): Orders {
  const area = areas(orders).find((a) => a.id === id);
  if (!area) return orders;
  const polygon = area.polygon ?? [];
  const last = polygon[polygon.length - 1];
  const point: LatLon = at ?? (last ? numberPair(last) : centreOf(orders) ?? [0, 0]);
  return updateArea(orders, id, { polygon: [...polygon, point] });
}
export function removeVertex(orders: Orders, id: string, index: number): Orders {
  const area = areas(orders).find((a) => a.id === id);
  if (!area) return orders;
  return updateArea(orders, id, { polygon: (area.polygon ?? []).filter((_, i) => i !== index) });
}
function centreOf(orders: Orders): LatLon | null {
  const pts = areas(orders).flatMap((a) => a.polygon ?? []).map(numberPair);
  if (pts.length === 0) return null;
  return [pts.reduce((s, p) => s + p[0], 0) / pts.length, pts.reduce((s, p) => s + p[1], 0) / pts.length];
}

// ---- Quantities ----

export function quantities(orders: Orders): Record<string, QuantitySpec> {
  return orders.quantities ?? {};
}
export function addQuantity(orders: Orders, name: string): { orders: Orders; error?: string } {
  if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(name)) return { orders, error: "A quantity name is letters, digits and _, e.g. depth_m." };
  if (quantities(orders)[name]) return { orders, error: `Quantity ${name} exists already.` };
  return { orders: { ...orders, quantities: { ...quantities(orders), [name]: {} } } };
}
export function updateQuantity(orders: Orders, name: string, changes: Record<string, unknown>): Orders {
  const all = quantities(orders);
  if (!all[name]) return orders;
  return { ...orders, quantities: { ...all, [name]: patch(all[name], changes) } };
}
export function deleteQuantity(orders: Orders, name: string): Orders {
  const rest = { ...quantities(orders) };
  delete rest[name];
  return patch(orders, { quantities: rest });
}

// ---- Norms ----

export function norms(orders: Orders): NormSpec[] {
  return orders.norms ?? [];
}
/** The orders with these norms. A norm being written may still lack its context (the check
 * reports it), which the server's type does not allow: the one place that says so. */
function withNorms(orders: Orders, list: NormSpec[]): Orders {
  return { ...orders, norms: list as Orders["norms"] };
}
/** A new norm is valid as created (the server refuses a norm without a context or without
 * exactly one modality): the first context the areas name (else a protected area), permitting
 * `true`, which constrains nothing until the operator writes the norm. */
export function addNorm(orders: Orders): { orders: Orders; id: string } {
  const id = freeId(norms(orders).map((n) => n.id), "N");
  const context = areas(orders).flatMap((a) => a.contexts ?? [])[0] ?? "marine_protected_area";
  return { orders: withNorms(orders, [...norms(orders), { id, context, permitted: "true" }]), id };
}
export function updateNorm(orders: Orders, id: string, changes: Record<string, unknown>): Orders {
  return withNorms(orders, norms(orders).map((n) => (n.id === id ? patch(n, changes) : n)));
}
export function normKind(norm: NormSpec): NormKind {
  return NORM_KINDS.find((k) => norm[k] !== undefined) ?? "forbidden";
}
/** Moves a norm's expression to another kind (forbidden, obligated, permitted). */
export function setNormKind(orders: Orders, id: string, kind: NormKind): Orders {
  const norm = norms(orders).find((n) => n.id === id);
  if (!norm) return orders;
  // The expression moves along; an empty one becomes `true`, so that the norm keeps a modality.
  const expr = norm[normKind(norm)] ?? "";
  return updateNorm(orders, id, { forbidden: undefined, obligated: undefined, permitted: undefined, [kind]: expr || "true" });
}
export function deleteNorm(orders: Orders, id: string): Orders {
  return patch(orders, { norms: norms(orders).filter((n) => n.id !== id) });
}

// ---- Vehicle profile ----

export function vehicles(orders: Orders): VehicleSpec[] {
  return (orders.vehicles as VehicleSpec[] | undefined) ?? [];
}
/** The orders with these vehicle profiles (a profile being written may be incomplete). */
function withVehicles(orders: Orders, list: VehicleSpec[]): Orders {
  return { ...orders, vehicles: list as Orders["vehicles"] };
}
/** The target vehicle's profile in the orders (the one `vehicle` names). */
export function targetVehicle(orders: Orders): VehicleSpec | undefined {
  return vehicles(orders).find((v) => v.id === orders.vehicle);
}
/** Adds a profile for the vehicle the orders name (or a new id) and targets it. */
export function addVehicle(orders: Orders, id?: string): Orders {
  const vid = id || (orders.vehicle as string | undefined) || freeId(vehicles(orders).map((v) => v.id), "vehicle-");
  if (vehicles(orders).some((v) => v.id === vid)) return { ...orders, vehicle: vid };
  return withVehicles({ ...orders, vehicle: vid }, [...vehicles(orders), { id: vid }]);
}
export function updateVehicle(orders: Orders, id: string, changes: Record<string, unknown>): Orders {
  return withVehicles(orders, vehicles(orders).map((v) => (v.id === id ? patch(v, changes) : v)));
}
/** Renames a vehicle profile and the orders' target when it named that profile. */
export function renameVehicle(orders: Orders, id: string, to: string): { orders: Orders; error?: string } {
  if (to === id) return { orders };
  if (!to) return { orders, error: "A vehicle needs an id." };
  if (vehicles(orders).some((v) => v.id === to)) return { orders, error: `Vehicle ${to} exists already.` };
  return {
    orders: withVehicles(
      { ...orders, vehicle: orders.vehicle === id ? to : orders.vehicle },
      vehicles(orders).map((v) => (v.id === id ? { ...v, id: to } : v)),
    ),
  };
}
export function addFeature(orders: Orders, vehicle: string): { orders: Orders; id: string } {
  const v = vehicles(orders).find((x) => x.id === vehicle);
  const id = freeId((v?.features ?? []).map((f) => f.id), "feature-");
  const feature: FeatureSpec = { id, fulfills: [], measures: [] };
  return { orders: updateVehicle(orders, vehicle, { features: [...(v?.features ?? []), feature] }), id };
}
export function updateFeature(orders: Orders, vehicle: string, id: string, changes: Record<string, unknown>): Orders {
  const v = vehicles(orders).find((x) => x.id === vehicle);
  if (!v) return orders;
  const features = (v.features ?? []).map((f) => {
    if (f.id !== id) return f;
    const updated = patch(f, changes);
    // Lists stay lists, even when empty.
    return { ...updated, fulfills: updated.fulfills ?? [], measures: updated.measures ?? [] };
  });
  return updateVehicle(orders, vehicle, { features });
}
export function renameFeature(orders: Orders, vehicle: string, id: string, to: string): { orders: Orders; error?: string } {
  const v = vehicles(orders).find((x) => x.id === vehicle);
  if (!v || to === id) return { orders };
  if (!to) return { orders, error: "A feature needs an id." };
  if ((v.features ?? []).some((f) => f.id === to)) return { orders, error: `Feature ${to} exists already.` };
  return { orders: updateVehicle(orders, vehicle, { features: (v.features ?? []).map((f) => (f.id === id ? { ...f, id: to } : f)) }) };
}
export function deleteFeature(orders: Orders, vehicle: string, id: string): Orders {
  const v = vehicles(orders).find((x) => x.id === vehicle);
  if (!v) return orders;
  return updateVehicle(orders, vehicle, { features: (v.features ?? []).filter((f) => f.id !== id) });
}

// ---- Copy and paste of goals ----

export const CLIPBOARD_FORMAT = "countersign.goals/1";
export interface Clip {
  format: typeof CLIPBOARD_FORMAT;
  goals: GoalSpec[];
  layout: Layout;
}

/** The selected goals (with their positions) as clipboard data. */
export function copyGoals(orders: Orders, layout: Layout, ids: Iterable<string>): Clip | null {
  const wanted = new Set(ids);
  const picked = goals(orders).filter((g) => wanted.has(g.id));
  if (picked.length === 0) return null;
  const at: Layout = {};
  for (const g of picked) if (layout[g.id]) at[g.id] = layout[g.id]!;
  return { format: CLIPBOARD_FORMAT, goals: structuredClone(picked), layout: at };
}

export function readClip(text: string | null | undefined): Clip | null {
  if (!text) return null;
  try {
    const data = JSON.parse(text) as Clip;
    if (data && data.format === CLIPBOARD_FORMAT && Array.isArray(data.goals)) return data;
  } catch {
    /* not ours */
  }
  return null;
}

/**
 * Pastes goals: an id that clashes with a goal, terminal or constraint gets the first free
 * G<n>; outcomes between pasted goals follow the renaming; outcomes to nodes that exist in the
 * target orders stay; others are dropped (the editor then shows SINK). Pasted goals are placed
 * `offset` from where they were copied. Answers the new ids in the clip's order.
 */
export function pasteGoals(
  orders: Orders,
  layout: Layout,
  clip: Clip,
  offset: Point = { x: 40, y: 40 },
): { orders: Orders; layout: Layout; ids: string[] } {
  const taken = new Set<string>([
    ...goals(orders).map((g) => g.id),
    ...terminals(orders).map((t) => t.id),
    ...((orders.constraints ?? []).map((c) => c.id)),
  ]);
  const renamed = new Map<string, string>();
  for (const g of clip.goals) {
    let id = g.id;
    if (taken.has(id)) id = freeId(taken, "G");
    taken.add(id);
    renamed.set(g.id, id);
  }
  const known = new Set([...goals(orders).map((g) => g.id), ...terminals(orders).map((t) => t.id)]);
  const pasted: GoalSpec[] = clip.goals.map((g) => {
    const next: GoalSpec["next"] = {};
    for (const o of OUTCOMES) {
      const targets = successors(g, o)
        .map((t) => renamed.get(t) ?? (known.has(t) ? t : null))
        .filter((t): t is string => t !== null);
      if (targets.length > 0) next[o] = targets.length === 1 ? targets[0]! : targets;
    }
    return { ...structuredClone(g), id: renamed.get(g.id)!, next };
  });
  const newLayout = { ...layout };
  clip.goals.forEach((g, i) => {
    const from = clip.layout[g.id] ?? { x: i * 30, y: i * 30 };
    newLayout[renamed.get(g.id)!] = { x: from.x + offset.x, y: from.y + offset.y };
  });
  const updated: Orders = { ...orders, goals: [...goals(orders), ...pasted] };
  if (orders.start == null && pasted.length > 0 && goals(orders).length === 0) updated.start = pasted[0]!.id;
  return { orders: updated, layout: newLayout, ids: pasted.map((g) => g.id) };
}
