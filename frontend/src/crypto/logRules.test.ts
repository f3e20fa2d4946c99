/** the surviving mutant (a key revoked before it signed), in
 * the browser's verifier: the log-wide rules name the entries, whatever the tables say. */
import { describe, expect, it } from "vitest";

import { checkLog, type RuleEvent } from "./logRules";
import { type ApprovalRecord, GENESIS, type LogEntryRow, verifyApproval } from "./verify";

const ev = (kind: string, detail: Record<string, unknown>): RuleEvent => ({ kind, mission: "m", detail });

describe("log-wide rules", () => {
  it("names two decisions on one submission (finding 4)", () => {
    const events = [
      ev("submission.created", { submission: 1, version: 1 }),
      ev("approval.approved", { submission: 1, key_id: "k" }),
      ev("approval.rejected", { submission: 1, key_id: "k" }),
    ];
    expect(checkLog(events)).toContain("log entries 1 and 2 both decide submission 1: one decision per submission");
  });

  it("names a second active submission of one version (finding 4)", () => {
    const events = [ev("submission.created", { submission: 1, version: 3 }), ev("submission.created", { submission: 2, version: 3 })];
    expect(checkLog(events)[0]).toContain("while submission 1 is still active");
  });

  it("names a key revoked before it signed", () => {
    const events = [
      ev("key.registered", { key_id: "k" }),
      ev("submission.created", { submission: 1, version: 1 }),
      ev("key.revoked", { key_id: "k" }),
      ev("approval.approved", { submission: 1, key_id: "k" }),
    ];
    expect(checkLog(events).join()).toContain("log entry 3 is signed with key k, revoked in log entry 2");
  });

  it("names a logged decision without an envelope (finding 5: a deleted approvals row)", () => {
    const events = [ev("submission.created", { submission: 1, version: 1 }), ev("approval.approved", { submission: 1, key_id: "k" })];
    expect(checkLog(events, [])[0]).toContain("log entry 1 records a signed decision (approval.approved) but the bundle holds no envelope");
    expect(checkLog(events, [1])).toEqual([]);
  });

  it("runs inside verifyApproval, which fails its rules check", async () => {
    const events = [
      ev("submission.created", { submission: 1, version: 1 }),
      ev("approval.approved", { submission: 1, key_id: "k" }),
      ev("approval.rejected", { submission: 1, key_id: "k" }),
    ];
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
      id: 1, mission: "m", version: 1, decision: "rejected", digest: "sha256:00", log_index: 2, envelope: "{}", orders: {},
      key: { key_id: "k", public_key: "", user: null },
      checkpoint: { size: 3, root: "00", note: "", key_id: "", public_key: "", signature: "" }, inclusion: null,
    } satisfies ApprovalRecord;
    const checks = await verifyApproval(record, entries);
    const chain = checks.find((c) => c.id === "chain")!;
    expect(chain.ok).toBe(true);
    const rules = checks.find((c) => c.id === "rules")!;
    expect(rules.ok).toBe(false);
    expect(rules.detail).toContain("log entries 1 and 2 both decide submission 1");
  });
});
