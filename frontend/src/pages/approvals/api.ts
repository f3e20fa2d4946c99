/** Types and calls of the approvals API (docs/api.md, "Approvals and audit") for these pages. */
import { api, type Schema, unwrap } from "../../api/client";
import type { LogEntryRow } from "../../crypto/verify";

export type { Submission } from "../../api/submissions";
export type Key = Schema<"KeyOut">;
export type ApprovalSummary = Schema<"ApprovalOut">;
/** A decision as recorded, with the log signer's receipt. */
export type RecordedDecision = Schema<"DecisionOut">;
export type { ApprovalPage } from "../../api/approvals";

export type PathSummary = Schema<"PathCountsOut">;
/** GET /api/missions/{id}/versions/{number}/review */
export type { Review } from "../../api/versions";
/** GET /api/approvals/{id} */
export type { ApprovalDetail } from "../../api/approvals";
/** The server's prepared statement: sign `pae` (which must equal PAE(payloadType, payload)). */
export type Prepared = Schema<"PreparedOut">;

/** Every approval record the server lists for a mission (pages of 500), for the browser
 * verifier to hold against the log. */
export async function loadMissionApprovals(mission: string): Promise<ApprovalSummary[]> {
  const rows: ApprovalSummary[] = [];
  let cursor: number | null | undefined;
  do {
    const query: { mission: string; limit: number; cursor?: number } = { mission, limit: 500 };
    if (cursor) query.cursor = cursor;
    const page = unwrap(await api.GET("/api/approvals", { params: { query } }));
    rows.push(...page.items);
    cursor = page.next_cursor;
  } while (cursor);
  return rows;
}

/** The log's first `size` entries (pages of up to 5,000). */
export async function loadEntries(size: number): Promise<LogEntryRow[]> {
  const rows: LogEntryRow[] = [];
  while (rows.length < size) {
    const limit = Math.min(5000, size - rows.length);
    const result = await api.GET("/api/log/entries", { params: { query: { start: rows.length, limit } } });
    const page: LogEntryRow[] = unwrap(result);
    if (page.length === 0) break;
    rows.push(...page);
  }
  return rows.slice(0, size);
}

export function approvalHref(id: number): string {
  return `/audit/${id}`;
}

export function reviewHref(mission: string, version: number): string {
  return `/missions/${encodeURIComponent(mission)}/versions/${version}/review`;
}

/** The printable approval document of a version. */
export function documentHref(mission: string, version: number): string {
  return `/missions/${encodeURIComponent(mission)}/versions/${version}/document`;
}

export function bundleHref(mission?: string): string {
  return mission ? `/api/audit/bundle?mission=${encodeURIComponent(mission)}` : "/api/audit/bundle";
}
