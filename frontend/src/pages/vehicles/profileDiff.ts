/**
 * The difference between two vehicle profiles, field by field, for the registry's version
 * history and for an approval whose profile the registry has changed since it was signed.
 * Empty values (absent, null, "", [], {}) count as the same: the server stores a profile
 * without the defaults its author did not write. Pure: no React, no API.
 */
import { canonicalJson } from "../../crypto/canonical";

export type Profile = Record<string, unknown>;

export interface ProfileChange {
  field: string;
  before: unknown;
  after: unknown;
}

function empty(value: unknown): boolean {
  if (value === undefined || value === null || value === "") return true;
  if (Array.isArray(value)) return value.length === 0;
  if (typeof value === "object") return Object.keys(value as object).length === 0;
  return false;
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** A list whose members are objects with distinct string ids (features, contingency rules). */
function byId(value: unknown): Map<string, unknown> | null {
  if (!Array.isArray(value) || value.length === 0) return null;
  const found = new Map<string, unknown>();
  for (const item of value) {
    if (!isRecord(item) || typeof item.id !== "string" || found.has(item.id)) return null;
    found.set(item.id, item);
  }
  return found;
}

/** Field by field, down to the nested field that changed: `envelope.depth_m`,
 * `budget.energy_wh`, `features[nav].measures`, not the whole envelope or feature list. Objects
 * are walked key by key, lists of objects with ids member by member (a member added or removed
 * is one change); anything else is compared whole. In a stable order: the "before" keys first. */
export function profileDiff(before: Profile, after: Profile): ProfileChange[] {
  const changes: ProfileChange[] = [];
  walk(before, after, "", changes, 0);
  return changes;
}

function walk(a: unknown, b: unknown, path: string, changes: ProfileChange[], depth: number): void {
  if (empty(a) && empty(b)) return;
  // Bounded: profiles are shallow; a hostile deep one is compared whole past this depth.
  if (depth < 8 && isRecord(a) && isRecord(b)) {
    for (const key of [...new Set([...Object.keys(a), ...Object.keys(b)])]) {
      walk(a[key], b[key], path ? `${path}.${key}` : key, changes, depth + 1);
    }
    return;
  }
  const left = byId(a);
  const right = byId(b);
  if (depth < 8 && left && right) {
    for (const id of [...new Set([...left.keys(), ...right.keys()])]) {
      walk(left.get(id), right.get(id), `${path}[${id}]`, changes, depth + 1);
    }
    return;
  }
  if (canonicalJson(a ?? null) !== canonicalJson(b ?? null)) changes.push({ field: path, before: a, after: b });
}

/** A value as a reviewer reads it: lists of words joined, anything else as compact JSON. */
export function showValue(value: unknown): string {
  if (empty(value)) return "(none)";
  if (Array.isArray(value) && value.every((v) => typeof v === "string")) return value.join(", ");
  if (typeof value === "string") return value;
  return JSON.stringify(value);
}
