/**
 * The difference between two sets of orders (countersign.orders/1), for the supervisor's
 * review: which goals, constraints, norms (and the other id-keyed lists) were added, removed or
 * changed, field by field, and which top-level fields changed. Pure: no React, no API.
 */
import { canonicalJson } from "../../crypto/canonical";

export type OrdersData = Record<string, unknown>;

export interface FieldChange {
  field: string;
  before: unknown;
  after: unknown;
}

export interface ItemChange {
  id: string;
  label: string;
  fields: FieldChange[];
}

export interface SectionDiff {
  key: string;
  label: string;
  added: { id: string; label: string }[];
  removed: { id: string; label: string }[];
  changed: ItemChange[];
}

export interface OrdersDiff {
  sections: SectionDiff[];
  fields: FieldChange[];
  /** Nothing differs. */
  same: boolean;
}

/** Id-keyed lists, in the order a reviewer reads them. */
export const SECTIONS: { key: string; label: string }[] = [
  { key: "goals", label: "Goals" },
  { key: "constraints", label: "Constraints" },
  { key: "norms", label: "Norms" },
  { key: "terminals", label: "Terminals" },
  { key: "properties", label: "Path properties" },
  { key: "areas", label: "Areas" },
  { key: "vehicles", label: "Vehicles" },
  { key: "quantities", label: "Quantities" },
];

const DEFAULT_TERMINALS = [
  { id: "COMPLETE", kind: "complete", title: "Mission complete" },
  { id: "ABORT", kind: "abort", title: "Mission abort" },
];

function same(a: unknown, b: unknown): boolean {
  return canonicalJson(a ?? null) === canonicalJson(b ?? null);
}

type Item = Record<string, unknown>;

function itemsOf(orders: OrdersData, key: string): Map<string, Item> {
  const items = new Map<string, Item>();
  let raw = orders[key];
  if (key === "terminals" && raw == null) raw = DEFAULT_TERMINALS;
  if (key === "quantities" && raw && typeof raw === "object" && !Array.isArray(raw)) {
    for (const [id, value] of Object.entries(raw as Record<string, unknown>)) {
      items.set(id, { id, ...(value as Item) });
    }
    return items;
  }
  if (!Array.isArray(raw)) return items;
  raw.forEach((value, index) => {
    if (value && typeof value === "object") {
      const item = value as Item;
      const id = typeof item.id === "string" ? item.id : `#${index + 1}`;
      if (!items.has(id)) items.set(id, item);
    }
  });
  return items;
}

function labelOf(item: Item, id: string): string {
  const title = item.title ?? item.text;
  return typeof title === "string" && title.trim() ? `${id} (${title.trim()})` : id;
}

function fieldChanges(before: Item, after: Item): FieldChange[] {
  const keys = [...new Set([...Object.keys(before), ...Object.keys(after)])].sort();
  return keys
    .filter((k) => !same(before[k], after[k]))
    .map((field) => ({ field, before: before[field], after: after[field] }));
}

/** What changed from `before` (the previously approved orders) to `after` (the reviewed ones). */
export function diffOrders(before: OrdersData, after: OrdersData): OrdersDiff {
  const sections: SectionDiff[] = SECTIONS.map(({ key, label }) => {
    const old = itemsOf(before, key);
    const now = itemsOf(after, key);
    const added = [...now].filter(([id]) => !old.has(id)).map(([id, item]) => ({ id, label: labelOf(item, id) }));
    const removed = [...old].filter(([id]) => !now.has(id)).map(([id, item]) => ({ id, label: labelOf(item, id) }));
    const changed = [...now]
      .filter(([id]) => old.has(id))
      .map(([id, item]) => ({ id, label: labelOf(item, id), fields: fieldChanges(old.get(id)!, item) }))
      .filter((c) => c.fields.length > 0);
    return { key, label, added, removed, changed };
  });
  const listed = new Set(SECTIONS.map((s) => s.key));
  const top = [...new Set([...Object.keys(before), ...Object.keys(after)])]
    .filter((k) => !listed.has(k))
    .sort();
  const fields = top
    .filter((k) => !same(before[k], after[k]))
    .map((field) => ({ field, before: before[field], after: after[field] }));
  const empty = sections.every((s) => !s.added.length && !s.removed.length && !s.changed.length);
  return { sections, fields, same: empty && fields.length === 0 };
}

/** A value as one short line of text for the diff table. */
export function showValue(value: unknown, max = 160): string {
  if (value === undefined) return "(none)";
  const text = typeof value === "string" ? value : JSON.stringify(value);
  return text.length > max ? `${text.slice(0, max - 1)}…` : text;
}

/** The diff as plain sentences (for a summary line and for tests). */
export function describeDiff(diff: OrdersDiff): string[] {
  const lines: string[] = [];
  for (const f of diff.fields) lines.push(`${f.field} changed: ${showValue(f.before)} → ${showValue(f.after)}`);
  for (const s of diff.sections) {
    for (const a of s.added) lines.push(`${s.label}: added ${a.label}`);
    for (const r of s.removed) lines.push(`${s.label}: removed ${r.label}`);
    for (const c of s.changed) lines.push(`${s.label}: changed ${c.id} (${c.fields.map((f) => f.field).join(", ")})`);
  }
  return lines;
}
