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

/** The fields that differ, in a stable order (the "before" profile's keys first). */
export function profileDiff(before: Profile, after: Profile): ProfileChange[] {
  const keys = [...new Set([...Object.keys(before), ...Object.keys(after)])];
  const changes: ProfileChange[] = [];
  for (const field of keys) {
    const a = before[field];
    const b = after[field];
    if (empty(a) && empty(b)) continue;
    if (canonicalJson(a ?? null) !== canonicalJson(b ?? null)) changes.push({ field, before: a, after: b });
  }
  return changes;
}

/** A value as a reviewer reads it: lists of words joined, anything else as compact JSON. */
export function showValue(value: unknown): string {
  if (empty(value)) return "(none)";
  if (Array.isArray(value) && value.every((v) => typeof v === "string")) return value.join(", ");
  if (typeof value === "string") return value;
  return JSON.stringify(value);
}
