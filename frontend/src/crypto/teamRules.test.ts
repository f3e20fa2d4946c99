/** A team approval's member digests in the browser's verifier: the shared vectors (also run by
 * tests/approvals/test_team_vectors.py against approvals/team_rules.py), built by the server's own
 * statement builder from the team exemplar. */
import { describe, expect, it } from "vitest";

import vectors from "./__fixtures__/team.json";
import { toBase64, utf8 } from "./bytes";
import { jsonDigest } from "./canonical";
import { PAYLOAD_TYPE, signEnvelope } from "./dsse";
import { memberOrdersDigests, teamProblems } from "./teamRules";
import { type ApprovalRecord, verifyApproval } from "./verify";

const orders = vectors.orders as Record<string, unknown>;

describe("team approvals", () => {
  it("recomputes every member's digest as the builder signed it, and the team digest as the subject", async () => {
    const team = vectors.statement.predicate.team as Record<string, string>;
    expect(Object.fromEntries((await memberOrdersDigests(orders.team))!)).toEqual(team);
    expect(await jsonDigest(orders.team)).toBe(`sha256:${vectors.statement.subject[0]!.digest.sha256}`);
  });

  for (const c of vectors.cases) {
    it(c.name, async () => {
      const predicate: Record<string, unknown> = { ...vectors.statement.predicate };
      delete predicate.team;
      if (c.team !== null) predicate.team = c.team;
      const problems = await teamProblems(orders[c.orders], predicate);
      expect(problems).toEqual(c.problems);
      for (const vehicle of c.names) expect(problems.join("\n")).toContain(`team member ${vehicle}:`);
    });
  }
});

describe("verifyApproval of a team's approval", () => {
  async function record(team: unknown): Promise<ApprovalRecord> {
    const keyPair = (await crypto.subtle.generateKey({ name: "Ed25519" }, true, ["sign", "verify"])) as CryptoKeyPair;
    const raw = new Uint8Array(await crypto.subtle.exportKey("raw", keyPair.publicKey));
    const predicate: Record<string, unknown> = { ...vectors.statement.predicate, team };
    const payload = utf8(JSON.stringify({ ...vectors.statement, predicate }));
    const envelope = await signEnvelope(PAYLOAD_TYPE, payload, keyPair.privateKey, "k");
    return {
      id: 1, mission: "pair", version: 1, decision: "approved", digest: await jsonDigest(orders.team), log_index: null, envelope,
      orders: orders.team, key: { key_id: "k", public_key: toBase64(raw), user: null },
      checkpoint: { size: 0, root: "00", note: "", key_id: "", public_key: "", signature: "" }, inclusion: null,
    };
  }

  it("passes the team check for the builder's member list and names the member otherwise", async () => {
    const team = vectors.statement.predicate.team as Record<string, string>;
    const good = (await verifyApproval(await record(team), [])).find((check) => check.id === "team")!;
    expect(good.ok).toBe(true);
    const [first, second] = Object.keys(team) as [string, string];
    const swapped = { [first]: team[second], [second]: team[first] };
    const bad = (await verifyApproval(await record(swapped), [])).find((check) => check.id === "team")!;
    expect(bad.ok).toBe(false);
    expect(bad.detail).toContain(`team member ${first}: the signed digest`);
  });
});
