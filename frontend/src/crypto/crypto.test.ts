/**
 * The browser's DSSE, RFC 6962 and RFC 8785 code against vectors computed by the Python
 * implementation (tests/approvals/test_browser_vectors.py writes and checks __fixtures__/vectors.json).
 */
import { describe, expect, it } from "vitest";

import vectors from "./__fixtures__/vectors.json";
import { fromBase64, fromHex, toBase64, toHex, utf8 } from "./bytes";
import { canonicalJson, jsonDigest } from "./canonical";
import { importPublicKey, keyId, pae, parseEnvelope, signEnvelope, verifyEnvelope } from "./dsse";
import { leafHash, nodeHash, rootOf, verifyInclusion } from "./merkle";
import { type ApprovalRecord, checkChain, type LogEntryRow, verifyApproval, verifyCheckpoint } from "./verify";

describe("DSSE PAE", () => {
  it.each(vectors.pae)("encodes $payloadType like the server", ({ payloadType, payload, pae: expected }) => {
    expect(toBase64(pae(payloadType, fromBase64(payload)))).toBe(expected);
  });

  it("counts bytes, not characters", () => {
    expect(new TextDecoder().decode(pae("t", utf8("é")))).toBe("DSSEv1 1 t 2 é");
    expect(new TextDecoder().decode(pae("é", utf8("t")))).toBe("DSSEv1 2 é 1 t");
  });

  it("verifies an envelope the Python code signed, and refuses one byte changed", async () => {
    const { public_key, key_id, text } = vectors.envelope;
    const key = await importPublicKey(public_key);
    expect(await keyId(fromBase64(public_key))).toBe(key_id);
    const envelope = parseEnvelope(text);
    expect(await verifyEnvelope(envelope, key)).toBe(true);
    const payload = fromBase64(envelope.payload);
    payload[0] = payload[0]! ^ 1;
    expect(await verifyEnvelope({ ...envelope, payload: toBase64(payload) }, key)).toBe(false);
  });

  it("signs with a non-extractable key so that the signature verifies", async () => {
    const pair = (await crypto.subtle.generateKey({ name: "Ed25519" }, false, ["sign", "verify"])) as CryptoKeyPair;
    expect(pair.privateKey.extractable).toBe(false);
    const text = await signEnvelope("application/vnd.in-toto+json", utf8("{}"), pair.privateKey, "kid");
    expect(await verifyEnvelope(parseEnvelope(text), pair.publicKey)).toBe(true);
  });

  it("refuses envelopes that are not one-signature DSSE", () => {
    expect(() => parseEnvelope("nope")).toThrow("not JSON");
    expect(() => parseEnvelope('{"payload":"","payloadType":"x","signatures":[]}')).toThrow("exactly one signature");
  });
});

describe("RFC 6962 Merkle tree", () => {
  const { entries, leaves, roots, proofs } = vectors.merkle;

  it("hashes leaves like the server", async () => {
    for (let i = 0; i < entries.length; i++) {
      expect(toHex(await leafHash(utf8(entries[i]!)))).toBe(leaves[i]);
    }
  });

  it("computes the root of every size", async () => {
    for (const [size, root] of Object.entries(roots)) {
      const some = leaves.slice(0, Number(size)).map((l) => fromHex(l));
      expect(toHex(await rootOf(some))).toBe(root);
    }
  });

  it("verifies every inclusion proof and refuses wrong ones", async () => {
    for (const { index, size, hashes } of proofs) {
      const root = fromHex(roots[String(size) as keyof typeof roots]);
      const leaf = fromHex(leaves[index]!);
      const proof = hashes.map((h) => fromHex(h));
      expect(await verifyInclusion(leaf, index, size, proof, root)).toBe(true);
      const other = fromHex(leaves[(index + 1) % leaves.length]!);
      if (size > 1) expect(await verifyInclusion(other, index, size, proof, root)).toBe(false);
      const wrongRoot = fromHex(roots[String(size) as keyof typeof roots]);
      wrongRoot[0] = wrongRoot[0]! ^ 1;
      expect(await verifyInclusion(leaf, index, size, proof, wrongRoot)).toBe(false);
      expect(await verifyInclusion(leaf, size, size, proof, root)).toBe(false);
    }
  });

  it("refuses a proof that stops at a subtree root", async () => {
    // Leaf 0 of 4 with only its sibling: the path ends at the root of leaves 0-1, not of 0-3.
    const [l0, l1] = [fromHex(leaves[0]!), fromHex(leaves[1]!)];
    expect(await verifyInclusion(l0, 0, 4, [l1], await nodeHash(l0, l1))).toBe(false);
  });
});

describe("RFC 8785 canonical JSON", () => {
  it.each(vectors.canonical.map((c, i) => ({ ...c, i })))("digests value $i like the server", async ({ value, digest }) => {
    expect(await jsonDigest(value)).toBe(digest);
  });

  it("sorts keys by UTF-16 code units and writes numbers as ECMAScript does", () => {
    // U+20AC sorts before U+1F600, whose first UTF-16 code unit is 0xD83D.
    expect(canonicalJson({ b: 1, a: [1e21, 0.1, 100], "\ud83d\ude00": true, "\u20ac": null })).toBe(
      '{"a":[1e+21,0.1,100],"b":1,"\u20ac":null,"\ud83d\ude00":true}',
    );
  });

  it("refuses NaN and the infinities, which JSON cannot hold", () => {
    for (const value of [NaN, Infinity, -Infinity]) {
      expect(() => canonicalJson({ a: [value] })).toThrow("JSON has no NaN or Infinity");
    }
  });
});

describe("verifying an approval in the browser", () => {
  it("checks the signed checkpoint from the Python code", async () => {
    expect(await verifyCheckpoint(vectors.checkpoint)).toBeNull();
    expect(await verifyCheckpoint({ ...vectors.checkpoint, size: 6 })).toContain("does not state size 6");
    const sig = fromBase64(vectors.checkpoint.signature);
    sig[5] = sig[5]! ^ 1;
    expect(await verifyCheckpoint({ ...vectors.checkpoint, signature: toBase64(sig) })).toContain("not signed by the log key");
  });

  it("names the entry whose change breaks the chain", async () => {
    const rows: LogEntryRow[] = vectors.merkle.entries.map((entry, index) => ({
      index,
      entry,
      leaf_hash: vectors.merkle.leaves[index]!,
    }));
    expect((await checkChain(rows)).problems).toEqual([]);
    const changed = rows.map((r) => ({ ...r }));
    changed[3]!.entry = changed[3]!.entry.replace('"n":3', '"n":9');
    const { problems } = await checkChain(changed);
    expect(problems).toContain("log entry 3 does not hash to the leaf hash recorded for it: it was changed");
    expect(problems.some((p) => p.startsWith("log entry 4 does not chain to entry 3"))).toBe(true);
  });

  it("checks the link of the first entry after the genesis one", async () => {
    const rows: LogEntryRow[] = vectors.merkle.entries.map((entry, index) => ({
      index,
      entry,
      leaf_hash: vectors.merkle.leaves[index]!,
    }));
    const data = JSON.parse(rows[1]!.entry) as { prev: string };
    data.prev = "1".repeat(64);
    rows[1]!.entry = canonicalJson(data);
    rows[1]!.leaf_hash = toHex(await leafHash(utf8(rows[1]!.entry)));
    const { problems } = await checkChain(rows);
    expect(problems.some((p) => p.startsWith("log entry 1 does not chain to entry 0"))).toBe(true);
  });

  it("passes a record built like the server's and fails a changed envelope naming its entry", async () => {
    const { record, rows, orders, envelope } = await serverLikeRecord();
    const good = await verifyApproval(record, rows);
    expect(good.filter((c) => !c.ok)).toEqual([]);

    const parsed = JSON.parse(envelope) as { signatures: { sig: string }[] };
    const sig = parsed.signatures[0]!.sig;
    parsed.signatures[0]!.sig = (sig[0] === "A" ? "B" : "A") + sig.slice(1);
    const bad = await verifyApproval({ ...record, envelope: JSON.stringify(parsed) }, rows);
    const failed = Object.fromEntries(bad.filter((c) => !c.ok).map((c) => [c.id, c.detail]));
    expect(Object.keys(failed).sort()).toEqual(["logged", "signature", "statement"]);
    expect(failed.logged).toBe("the envelope differs from the one logged in log entry 2");

    const changedOrders = await verifyApproval({ ...record, orders: { ...orders, id: "n" } }, rows);
    expect(changedOrders.find((c) => c.id === "orders")?.ok).toBe(false);

    // Finding 2: rows INSERTed behind the app's back carry no receipt of the log signer (a
    // database writer has no log key), or one made with another key: named by entry.
    const otherKey = (await crypto.subtle.generateKey({ name: "Ed25519" }, false, ["sign", "verify"])) as CryptoKeyPair;
    const forged = rows.map((r) => ({ ...r }));
    forged[0]!.receipt = null;
    forged[2]!.receipt = await receiptFor(otherKey.privateKey, "countersign-log/1", 2, forged[2]!.leaf_hash);
    const unreceipted = await verifyApproval(record, forged);
    const receipts = unreceipted.find((c) => c.id === "receipts")!;
    expect(receipts.ok).toBe(false);
    expect(receipts.detail).toBe(
      "log entry 0 (key.registered) carries no receipt from the log signer: it was not appended by the app's log signer; " +
        "log entry 2 (approval.approved) has a receipt not signed by the log key",
    );
  });

  it("refuses a statement signed for another version or mission of the same orders", async () => {
    // Versions 1 and 2 of a mission can hold the same orders (same digest): only the signed
    // statement's version and mission tell which one the supervisor approved.
    const { record, rows } = await serverLikeRecord();
    for (const other of [{ version: 2 }, { mission: "n" }]) {
      const checks = await verifyApproval({ ...record, ...other }, rows);
      const failed = checks.filter((c) => !c.ok).map((c) => [c.id, c.detail]);
      expect(failed).toEqual([["statement", "it names another mission or version"]]);
    }
  });

  it("refuses a statement whose digest, decision or supervisor is not the record's", async () => {
    const other = await jsonDigest({ id: "other" });
    const cases: [RecordOptions, string][] = [
      [{ signedDigest: other }, `it signs ${other}, not `],
      [{ predicate: { decision: "rejected" } }, "it signs the decision rejected, not approved"],
      [{ predicate: { supervisor: "mallory" } }, "signed with sup's key but names mallory"],
    ];
    for (const [options, words] of cases) {
      const { record, rows } = await serverLikeRecord(options);
      const failed = (await verifyApproval(record, rows)).filter((c) => !c.ok);
      expect(failed.map((c) => c.id)).toEqual(["statement"]);
      expect(failed[0]!.detail).toContain(words);
    }
  });

  it("refuses orders digests the log did not record", async () => {
    const { record, rows } = await serverLikeRecord({ loggedDigest: await jsonDigest({ id: "other" }) });
    const failed = (await verifyApproval(record, rows)).filter((c) => !c.ok);
    expect(failed.map((c) => [c.id, c.detail])).toEqual([
      ["logged", "the orders digest differs from the one logged in log entry 2"],
    ]);
  });

  it("judges the signing key at the time of signing", async () => {
    // Revoked after it signed: the approval stands.
    const revokedLater = await serverLikeRecord({ later: (kid) => [{ kind: "key.revoked", detail: { key_id: kid } }] });
    expect((await verifyApproval(revokedLater.record, revokedLater.rows)).filter((c) => !c.ok)).toEqual([]);
    // Registered only after it signed: the key was not valid then.
    const { record, rows } = await serverLikeRecord({ registeredAfter: true });
    const key = (await verifyApproval(record, rows)).find((c) => c.id === "key")!;
    expect(key.ok).toBe(false);
    expect(key.detail).toContain("was not registered in the log before log entry 1");
  });

  it("refuses an inclusion proof made for another tree size", async () => {
    const { record, rows } = await serverLikeRecord();
    const checks = await verifyApproval({ ...record, inclusion: { ...record.inclusion!, size: 4 } }, rows);
    expect(checks.filter((c) => !c.ok).map((c) => c.id)).toEqual(["inclusion"]);
  });
});

async function receiptFor(key: CryptoKey, origin: string, index: number, leaf: string): Promise<string> {
  const time = "2026-12-01T00:00:00Z";
  const message = `countersign-receipt/v1\n${origin}\n${index}\n${leaf}\n${time}\n`;
  const signature = new Uint8Array(await crypto.subtle.sign({ name: "Ed25519" }, key, utf8(message)));
  return JSON.stringify({ format: "countersign-receipt/v1", origin, index, leaf, time, signature: toBase64(signature) });
}

interface RecordOptions {
  /** Overrides of the signed statement's predicate. */
  predicate?: Record<string, unknown>;
  /** The digest the statement signs (default: the orders'). */
  signedDigest?: string;
  /** The orders digest the log records for the approval (default: the orders'). */
  loggedDigest?: string;
  /** The key's registration is logged before the approval (default) or after it. */
  registeredAfter?: boolean;
  /** Events logged after the approval, given the signing key's id. */
  later?: (kid: string) => { kind: string; detail: Record<string, unknown> }[];
}

/** RFC 6962 audit path of leaf `index` (section 2.1.1 PATH). */
async function inclusionPath(leaves: Uint8Array[], index: number): Promise<Uint8Array[]> {
  if (leaves.length <= 1) return [];
  let k = 1;
  while (k * 2 < leaves.length) k *= 2;
  return index < k
    ? [...(await inclusionPath(leaves.slice(0, k), index)), await rootOf(leaves.slice(k))]
    : [...(await inclusionPath(leaves.slice(k), index - k)), await rootOf(leaves.slice(0, k))];
}

/** An approval record and its log as the server builds them, signed by fresh keys. */
async function serverLikeRecord(options: RecordOptions = {}): Promise<{ record: ApprovalRecord; rows: LogEntryRow[]; orders: { id: string; goals: { id: string }[] }; envelope: string }> {
  const pair = (await crypto.subtle.generateKey({ name: "Ed25519" }, false, ["sign", "verify"])) as CryptoKeyPair;
  const raw = new Uint8Array(await crypto.subtle.exportKey("raw", pair.publicKey));
  const kid = await keyId(raw);
  const publicKey = toBase64(raw);
  const orders = { id: "m", goals: [{ id: "G1" }] };
  const digest = await jsonDigest(orders);
  const statement = {
    subject: [{ name: "m@v1", digest: { sha256: (options.signedDigest ?? digest).slice(7) } }],
    predicate: { mission: "m", version: 1, decision: "approved", supervisor: "sup", ...options.predicate },
  };
  const envelope = await signEnvelope("application/vnd.in-toto+json", utf8(JSON.stringify(statement)), pair.privateKey, kid);
  const envelopeDigest = `sha256:${toHex(new Uint8Array(await crypto.subtle.digest("SHA-256", utf8(envelope))))}`;
  const registration = { kind: "key.registered", detail: { key_id: kid, public_key: publicKey } };
  const approval = {
    kind: "approval.approved",
    detail: { envelope_digest: envelopeDigest, orders_digest: options.loggedDigest ?? digest },
  };
  const events = [
    ...(options.registeredAfter ? [] : [registration]),
    { kind: "submission.created", detail: {} },
    approval,
    ...(options.registeredAfter ? [registration] : []),
    ...(options.later?.(kid) ?? []),
  ];
  const logIndex = events.indexOf(approval);
  const rows: LogEntryRow[] = [];
  let prev = "0".repeat(64);
  for (const [index, event] of events.entries()) {
    const entry = canonicalJson({ index, prev, event });
    prev = toHex(await leafHash(utf8(entry)));
    rows.push({ index, entry, leaf_hash: prev });
  }
  const logKey = (await crypto.subtle.generateKey({ name: "Ed25519" }, false, ["sign", "verify"])) as CryptoKeyPair;
  const logRaw = new Uint8Array(await crypto.subtle.exportKey("raw", logKey.publicKey));
  const leaves = await Promise.all(rows.map((r) => leafHash(utf8(r.entry))));
  const root = await rootOf(leaves);
  const note = `countersign-log/1\n${rows.length}\n${toBase64(root)}\n`;
  const signature = new Uint8Array(await crypto.subtle.sign({ name: "Ed25519" }, logKey.privateKey, utf8(note)));
  for (const row of rows) row.receipt = await receiptFor(logKey.privateKey, "countersign-log/1", row.index, row.leaf_hash);
  const record: ApprovalRecord = {
    id: 1,
    mission: "m",
    version: 1,
    decision: "approved",
    digest,
    log_index: logIndex,
    envelope,
    orders,
    key: { key_id: kid, public_key: publicKey, user: "sup" },
    checkpoint: { size: rows.length, root: toHex(root), note, key_id: await keyId(logRaw), public_key: toBase64(logRaw), signature: toBase64(signature) },
    inclusion: { index: logIndex, size: rows.length, hashes: (await inclusionPath(leaves, logIndex)).map((h) => toHex(h)) },
  };
  return { record, rows, orders, envelope };
}
