/** The browser signs only a statement that cites exactly what the review showed. */
import { describe, expect, it } from "vitest";

import { toBase64, utf8 } from "../../crypto/bytes";
import { pae } from "../../crypto/dsse";
import type { StoredKey } from "../../crypto/keystore";
import type { Prepared } from "./api";
import { signPrepared } from "./signing";

const DIGEST = `sha256:${"a".repeat(64)}`;
const CAMPAIGN = `sha256:${"c".repeat(64)}`;
const OTHER = `sha256:${"d".repeat(64)}`;
const TYPE = "application/vnd.in-toto+json";

function prepared(predicate: Record<string, unknown>): Prepared {
  const statement = { subject: [{ name: "m@v1", digest: { sha256: "a".repeat(64) } }], predicate };
  const payload = utf8(JSON.stringify(statement));
  return { payloadType: TYPE, payload: toBase64(payload), pae: toBase64(pae(TYPE, payload)), statement } as unknown as Prepared;
}

async function key(): Promise<StoredKey> {
  const keyPair = (await crypto.subtle.generateKey({ name: "Ed25519" }, false, ["sign", "verify"])) as CryptoKeyPair;
  return { id: "x", server: "s", user: "u", keyId: "k1", publicKey: "", name: "n", createdAt: "", keyPair };
}

const base = { decision: "approved", submission: 3, key_id: "k1" };
const shown = { digest: DIGEST, decision: "approved", submission: 3 };

describe("signPrepared", () => {
  it("signs a statement citing exactly the campaigns and rehearsal shown", async () => {
    const envelope = await signPrepared(prepared({ ...base, campaigns: [CAMPAIGN], rehearsal_digest: null }), await key(), {
      ...shown,
      rehearsal: null,
      campaigns: [CAMPAIGN],
    });
    expect(JSON.parse(envelope).signatures).toHaveLength(1);
  });

  it("refuses a statement citing a campaign the review did not show", async () => {
    await expect(
      signPrepared(prepared({ ...base, campaigns: [CAMPAIGN, OTHER] }), await key(), { ...shown, campaigns: [CAMPAIGN] }),
    ).rejects.toThrow("other rehearsal campaigns");
  });

  it("refuses a statement that drops a campaign the review showed", async () => {
    await expect(signPrepared(prepared(base), await key(), { ...shown, campaigns: [CAMPAIGN] })).rejects.toThrow(
      "other rehearsal campaigns",
    );
  });

  it("refuses a statement naming other checks than those of the report shown", async () => {
    const checker = `sha256:${"e".repeat(64)}`;
    const signed = await signPrepared(prepared({ ...base, checker }), await key(), { ...shown, checker });
    expect(JSON.parse(signed).signatures).toHaveLength(1);
    await expect(signPrepared(prepared({ ...base, checker: OTHER }), await key(), { ...shown, checker })).rejects.toThrow(
      "other checks",
    );
    await expect(signPrepared(prepared(base), await key(), { ...shown, checker })).rejects.toThrow("other checks");
  });

  it("refuses a statement citing another rehearsal record", async () => {
    await expect(
      signPrepared(prepared({ ...base, rehearsal_digest: OTHER }), await key(), { ...shown, rehearsal: null, campaigns: [] }),
    ).rejects.toThrow("another rehearsal record");
  });
});

describe("signPrepared on a team's orders", () => {
  it("signs only a statement whose member digests are those of the reviewed team", async () => {
    const { default: vectors } = await import("../../crypto/__fixtures__/team.json");
    const team = vectors.statement.predicate.team as Record<string, string>;
    const orders = vectors.orders.team;
    const ok = await signPrepared(prepared({ ...base, team }), await key(), { ...shown, orders });
    expect(JSON.parse(ok).signatures).toHaveLength(1);
    const [first] = Object.keys(team);
    const missing = Object.fromEntries(Object.entries(team).filter(([v]) => v !== first));
    await expect(signPrepared(prepared({ ...base, team: missing }), await key(), { ...shown, orders })).rejects.toThrow(
      `team member ${first!}: the statement signs no digest for it`,
    );
  });
});
