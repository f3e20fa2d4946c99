/** Types and calls of the approvals API (docs/api.md, "Approvals and audit") for these pages. */
import { api, type Finding, type MissionPath, unwrap } from "../../api/client";
import type { components } from "../../api/schema";
import type { ApprovalRecord, LogEntryRow } from "../../crypto/verify";
import type { OutcomeFigures } from "./probabilities";

export type Submission = components["schemas"]["SubmissionOut"];
export type Key = components["schemas"]["KeyOut"];
export type ApprovalSummary = components["schemas"]["ApprovalOut"];
export type ApprovalPage = components["schemas"]["ApprovalPage"];

export interface PathSummary {
  count: number;
  by_terminal: Record<string, number>;
}

/** GET /api/missions/{id}/versions/{number}/review */
export interface Review {
  mission: string;
  version: number;
  digest: string;
  author: string | null;
  created_at: string;
  orders: Record<string, unknown>;
  plain: string;
  /** The contingency rules, one plain-language sentence each ([] when none or unreadable). */
  rules: string[];
  ok: boolean;
  findings: Finding[];
  paths: PathSummary | null;
  path_items: MissionPath[];
  /** Outcome probabilities (issue 20); absent when the orders declare none. */
  probabilities?: OutcomeFigures | null;
  submissions: Submission[];
  previous: { version: number; digest: string; approval: number; state: string; orders: Record<string, unknown> } | null;
  may_submit: boolean;
  submit_refusal: string | null;
  may_decide: boolean;
  decide_refusal: string | null;
}

/** GET /api/approvals/{id} */
export interface ApprovalDetail extends ApprovalRecord {
  /** How the row disagrees with its log entry (empty: agrees). */
  integrity?: string[];
  vehicle: string | null;
  reason: string;
  revokes: number | null;
  operator: string | null;
  supervisor: string | null;
  key_id: string;
  submission: number;
  created_at: string;
  statement: { predicate?: Record<string, unknown>; subject?: { name?: string }[] };
  plain: string;
  rules: string[];
  findings: Finding[];
  paths: PathSummary | null;
  rehearsal: unknown;
  key: ApprovalRecord["key"] & { name: string; status: string; created_at: string; revoked_at: string | null };
}

/** The server's prepared statement: sign `pae` (which must equal PAE(payloadType, payload)). */
export interface Prepared {
  payloadType: string;
  payload: string;
  pae: string;
  statement: { subject?: { name?: string; digest?: Record<string, string> }[]; predicate?: Record<string, unknown> };
}

export async function loadReview(mission: string, version: number): Promise<Review> {
  const result = await api.GET("/api/missions/{mission_id}/versions/{number}/review", {
    params: { path: { mission_id: mission, number: version } },
  });
  return unwrap(result) as unknown as Review;
}

export async function loadApproval(id: number): Promise<ApprovalDetail> {
  const result = await api.GET("/api/approvals/{approval_id}", { params: { path: { approval_id: id } } });
  return unwrap(result) as unknown as ApprovalDetail;
}

/** Every approval record the server lists for a mission (pages of 500), for the browser
 * verifier to hold against the log (issue 14 finding 5). */
export async function loadMissionApprovals(mission: string): Promise<ApprovalSummary[]> {
  const rows: ApprovalSummary[] = [];
  let cursor: number | null | undefined;
  do {
    const query: { mission: string; limit: number; cursor?: number } = { mission, limit: 500 };
    if (cursor) query.cursor = cursor;
    const page = unwrap(await api.GET("/api/approvals", { params: { query } })) as ApprovalPage;
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
    const page = unwrap(result) as unknown as LogEntryRow[];
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

export function bundleHref(mission?: string): string {
  return mission ? `/api/audit/bundle?mission=${encodeURIComponent(mission)}` : "/api/audit/bundle";
}
