/** In the browser's verifier: the shared vectors (also run by
 * tests/web/test_role_rules.py against the Python rule), and checkLog carrying the rule. */
import { describe, expect, it } from "vitest";

import vectors from "./__fixtures__/roles.json";
import { checkLog } from "./logRules";
import { checkRoles, type RoleEvent } from "./roleRules";
import { type ApprovalRecord, GENESIS, type LogEntryRow, verifyApproval } from "./verify";

describe("roles from the log", () => {
  for (const c of vectors.cases) {
    it(c.name, () => {
      expect(checkRoles(c.events as RoleEvent[])).toEqual(c.problems);
    });
  }

  it("is one of the log-wide rules (an operator promoted in the table approves)", () => {
    const c = vectors.cases[0]!;
    expect(checkLog(c.events as RoleEvent[])).toEqual(c.problems);
  });

  it("fails verifyApproval's rules check on the record of such an approval", async () => {
    const c = vectors.cases[0]!;
    let prev = GENESIS;
    const entries: LogEntryRow[] = [];
    for (const [index, event] of c.events.entries()) {
      const entry = JSON.stringify({ event, index, prev });
      const digest = new Uint8Array(await crypto.subtle.digest("SHA-256", new Uint8Array([0, ...new TextEncoder().encode(entry)])));
      const hex = Array.from(digest, (b) => b.toString(16).padStart(2, "0")).join("");
      entries.push({ index, entry, leaf_hash: hex });
      prev = hex;
    }
    const record = {
      id: 1, mission: "m", version: 1, decision: "approved", digest: "sha256:00", log_index: 8, envelope: "{}", orders: {},
      key: { key_id: "k", public_key: "", user: null },
      checkpoint: { size: entries.length, root: "00", note: "", key_id: "", public_key: "", signature: "" }, inclusion: null,
    } satisfies ApprovalRecord;
    const rules = (await verifyApproval(record, entries)).find((check) => check.id === "rules")!;
    expect(rules.ok).toBe(false);
    expect(rules.detail).toContain("log entry 8 (approval.approved) by olga, but the log made olga operator in log entry 1: only an enabled supervisor decides");
  });
});
