import { describe, expect, it } from "vitest";

import vectors from "./__fixtures__/vectors.json";
import { fromBase64, toBase64 } from "./bytes";
import { keyId } from "./dsse";
import { fingerprint } from "./keystore";
import {
  comparePin,
  forgetPin,
  loadPin,
  parseLogKey,
  PIN_LABEL,
  pinCheck,
  type PinStorage,
  pinLogKey,
  pinStorageKey,
} from "./logkey";

const ORIGIN = "https://countersign.example";
const OTHER_ORIGIN = "http://127.0.0.1:8000";

/** localStorage's interface over a Map. */
function memory(): PinStorage & { map: Map<string, string> } {
  const map = new Map<string, string>();
  return {
    map,
    getItem: (key) => map.get(key) ?? null,
    setItem: (key, value) => void map.set(key, value),
    removeItem: (key) => void map.delete(key),
  };
}

async function newKey(): Promise<{ publicKey: string; keyId: string }> {
  const pair = (await crypto.subtle.generateKey({ name: "Ed25519" }, true, ["sign", "verify"])) as CryptoKeyPair;
  const raw = new Uint8Array(await crypto.subtle.exportKey("raw", pair.publicKey));
  return { publicKey: toBase64(raw), keyId: await keyId(raw) };
}

function pem(publicKey: string): string {
  const spki = new Uint8Array([0x30, 0x2a, 0x30, 0x05, 0x06, 0x03, 0x2b, 0x65, 0x70, 0x03, 0x21, 0x00, ...fromBase64(publicKey)]);
  return `-----BEGIN PUBLIC KEY-----\n${toBase64(spki)}\n-----END PUBLIC KEY-----\n`;
}

describe("reading a log key", () => {
  it("reads the base64 of the raw key, as the server and --log-key give it, and computes its id", async () => {
    const { public_key, key_id } = vectors.envelope;
    expect(await parseLogKey(`  ${public_key}\n`)).toEqual({ publicKey: public_key, keyId: key_id });
  });

  it("reads a PEM public key (openssl pkey -pubout) as the same key", async () => {
    const key = await newKey();
    expect(await parseLogKey(pem(key.publicKey))).toEqual(key);
  });

  it("refuses what is not an Ed25519 public key", async () => {
    await expect(parseLogKey("")).rejects.toThrow("enter the log's public key");
    await expect(parseLogKey("not base64!")).rejects.toThrow("not valid base64");
    await expect(parseLogKey(toBase64(new Uint8Array(31)))).rejects.toThrow("32 bytes");
    await expect(parseLogKey("-----BEGIN PRIVATE KEY-----\nAAAA\n-----END PRIVATE KEY-----")).rejects.toThrow("PEM PUBLIC KEY");
  });
});

describe("pinning the log key", () => {
  it("is unpinned at first: no check, the presented key with its id", async () => {
    const storage = memory();
    const key = await newKey();
    const state = await comparePin(await loadPin(storage, ORIGIN), key.publicKey);
    expect(state).toEqual({ kind: "unpinned", presented: key });
    expect(pinCheck(state)).toBeNull();
  });

  it("pins on first use per origin, and a later visit matches", async () => {
    const storage = memory();
    const key = await newKey();
    const pinned = await pinLogKey(storage, ORIGIN, key.publicKey, "first use", new Date("2026-11-28T12:00:00Z"));
    expect(pinned).toEqual({ ...key, origin: ORIGIN, pinnedAt: "2026-11-28T12:00:00.000Z", source: "first use" });
    expect([...storage.map.keys()]).toEqual([pinStorageKey(ORIGIN)]);

    const state = await comparePin(await loadPin(storage, ORIGIN), key.publicKey);
    expect(state.kind).toBe("matches");
    const check = pinCheck(state)!;
    expect(check).toMatchObject({ id: "pin", label: PIN_LABEL, ok: true });
    expect(check.detail).toContain(fingerprint(key.keyId));
    expect(check.detail).toContain("2026-11-28");
    // another server origin has its own pin
    expect((await loadPin(storage, OTHER_ORIGIN)).pinned).toBeNull();
  });

  it("fails the check naming both fingerprints when the server presents another key", async () => {
    const storage = memory();
    const [pinnedKey, presentedKey] = [await newKey(), await newKey()];
    await pinLogKey(storage, ORIGIN, pem(pinnedKey.publicKey), "entered");
    const state = await comparePin(await loadPin(storage, ORIGIN), presentedKey.publicKey);
    expect(state).toMatchObject({ kind: "differs", pinned: { ...pinnedKey, source: "entered" }, presented: presentedKey });
    const check = pinCheck(state)!;
    expect(check.ok).toBe(false);
    expect(check.label).toBe("Log key matches the pinned key");
    expect(check.detail).toContain(`the server presents log key ${fingerprint(presentedKey.keyId)}`);
    expect(check.detail).toContain(`this browser pinned log key ${fingerprint(pinnedKey.keyId)}`);
  });

  it("replaces a pin with a new one and forgets it", async () => {
    const storage = memory();
    const [first, second] = [await newKey(), await newKey()];
    await pinLogKey(storage, ORIGIN, first.publicKey, "first use");
    await pinLogKey(storage, ORIGIN, second.publicKey, "entered");
    expect((await loadPin(storage, ORIGIN)).pinned?.keyId).toBe(second.keyId);
    forgetPin(storage, ORIGIN);
    expect(await loadPin(storage, ORIGIN)).toEqual({ pinned: null, problem: null });
  });

  it("does not store a key it cannot read", async () => {
    const storage = memory();
    await expect(pinLogKey(storage, ORIGIN, "AAAA", "entered")).rejects.toThrow("32 bytes");
    expect(storage.map.size).toBe(0);
  });

  it("fails closed on a damaged pin, and on a server key that is not a key", async () => {
    const storage = memory();
    const key = await newKey();
    const other = await newKey();
    storage.setItem(pinStorageKey(ORIGIN), "{not json");
    let state = await comparePin(await loadPin(storage, ORIGIN), key.publicKey);
    expect(state.kind).toBe("unusable");
    expect(pinCheck(state)).toMatchObject({ ok: false, detail: expect.stringContaining("cannot be read") });

    storage.setItem(pinStorageKey(ORIGIN), JSON.stringify({ publicKey: key.publicKey, keyId: other.keyId }));
    state = await comparePin(await loadPin(storage, ORIGIN), key.publicKey);
    expect(pinCheck(state)).toMatchObject({ ok: false, detail: expect.stringContaining("not the hash of its key") });

    await pinLogKey(storage, ORIGIN, key.publicKey, "first use");
    state = await comparePin(await loadPin(storage, ORIGIN), "garbage");
    expect(pinCheck(state)).toMatchObject({ ok: false, detail: expect.stringContaining("the server's log key is unusable") });
  });
});
