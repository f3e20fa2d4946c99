/** In the browser: deleting a revocation's approvals row left the approval
 * looking valid; the browser now holds the server's records against the log. */
import { describe, expect, it } from "vitest";

import { checkRecords, type RecordEvent } from "./recordRules";
import { type ApprovalRecord, GENESIS, type LogEntryRow, verifyApproval } from "./verify";

const ev = (kind: string, detail: Record<string, unknown>): RecordEvent => ({ kind, mission: "m", detail });

// Approval 1 (log entry 1) approves submission 1; approval 2 (log entry 2) revokes it.
const events = [
  ev("submission.created", { submission: 1, version: 1 }),
  ev("approval.approved", { submission: 1, key_id: "k", revokes: null }),
  ev("approval.revoked", { submission: 1, key_id: "k", revokes: 1 }),
];
const approval = { id: 1, log_index: 1, revokes: null };
const revocation = { id: 2, log_index: 2, revokes: 1 };

describe("approval records against the log", () => {
  it("passes when every logged decision has its record", () => {
    expect(checkRecords(events, "m", 1, [approval, revocation])).toEqual([]);
  });

  it("names a deleted revocation row (finding 5)", () => {
    expect(checkRecords(events, "m", 1, [approval])).toEqual([
      "log entry 2 revokes approval 1, but the server shows it as not revoked: it is revoked (its revocation's approvals row was removed?)",
      "log entry 2 records a signed decision (approval.revoked) on m, but the server has no approval record for it (its approvals row was removed?)",
    ]);
  });

  it("names a logged decision with no record, and ignores other missions", () => {
    const other: RecordEvent = { kind: "approval.approved", mission: "n", detail: { submission: 9 } };
    expect(checkRecords([...events, other], "m", 2, [revocation])).toEqual([
      "log entry 1 records a signed decision (approval.approved) on m, but the server has no approval record for it (its approvals row was removed?)",
    ]);
  });

  it("fails verifyApproval's records check when the rows are given", async () => {
    let prev = GENESIS;
    const entries: LogEntryRow[] = [];
    for (const [index, event] of events.entries()) {
      const entry = JSON.stringify({ event, index, prev });
      const digest = new Uint8Array(await crypto.subtle.digest("SHA-256", new Uint8Array([0, ...new TextEncoder().encode(entry)])));
      const hex = Array.from(digest, (b) => b.toString(16).padStart(2, "0")).join("");
      entries.push({ index, entry, leaf_hash: hex });
      prev = hex;
    }
    const record = {
      id: 1, mission: "m", version: 1, decision: "approved", digest: "sha256:00", log_index: 1, envelope: "{}", orders: {},
      key: { key_id: "k", public_key: "", user: null },
      checkpoint: { size: 3, root: "00", note: "", key_id: "", public_key: "", signature: "" }, inclusion: null,
    } satisfies ApprovalRecord;
    const without = await verifyApproval(record, entries);
    expect(without.find((c) => c.id === "records")).toBeUndefined();
    const checks = await verifyApproval(record, entries, [approval]);
    const records = checks.find((c) => c.id === "records")!;
    expect(records.ok).toBe(false);
    expect(records.detail).toContain("log entry 2 revokes approval 1, but the server shows it as not revoked");
    const fine = (await verifyApproval(record, entries, [approval, revocation])).find((c) => c.id === "records")!;
    expect(fine.ok).toBe(true);
  });
});
