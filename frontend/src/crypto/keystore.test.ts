import { describe, expect, it } from "vitest";

import { fromBase64 } from "./bytes";
import { keyId } from "./dsse";
import { fingerprint, generateSigningKey } from "./keystore";

describe("signing keys", () => {
  it("generates a non-extractable Ed25519 key whose id is the SHA-256 of the raw public key", async () => {
    const key = await generateSigningKey();
    expect(key.keyPair.privateKey.extractable).toBe(false);
    expect(key.keyPair.privateKey.algorithm.name).toBe("Ed25519");
    expect(fromBase64(key.publicKey)).toHaveLength(32);
    expect(await keyId(fromBase64(key.publicKey))).toBe(key.keyId);
    await expect(crypto.subtle.exportKey("pkcs8", key.keyPair.privateKey)).rejects.toThrow();
  });

  it("shows a fingerprint as groups of four hex digits", () => {
    expect(fingerprint("3aecd0a19cd9f0f2aa")).toBe("3aec d0a1 9cd9 f0f2");
    expect(fingerprint("3aecd0a1", 1)).toBe("3aec");
  });
});
