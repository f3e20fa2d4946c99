/**
 * DSSE v1 envelopes signed with Ed25519 (backend/countersign/approvals/dsse.py): the
 * pre-authentication encoding (PAE) is what is signed; a key id is the hex SHA-256 of the raw
 * 32-byte public key, which travels as standard base64.
 */
import { concat, fromBase64, sha256Hex, toBase64, utf8 } from "./bytes";

export const PAYLOAD_TYPE = "application/vnd.in-toto+json";
export const ED25519 = { name: "Ed25519" } as const;

export interface Envelope {
  payloadType: string;
  payload: string;
  signatures: { keyid?: string; sig: string }[];
}

/** `DSSEv1 <len(type)> <type> <len(payload)> <payload>`, lengths in bytes, in ASCII decimal. */
export function pae(payloadType: string, payload: Uint8Array): Uint8Array<ArrayBuffer> {
  const kind = utf8(payloadType);
  return concat(utf8(`DSSEv1 ${kind.length} `), kind, utf8(` ${payload.length} `), payload);
}

export async function keyId(rawPublicKey: Uint8Array<ArrayBuffer>): Promise<string> {
  return sha256Hex(rawPublicKey);
}

/** Imports a public key given as standard base64 of its raw 32 bytes. */
export async function importPublicKey(text: string): Promise<CryptoKey> {
  const raw = fromBase64(text, "the public key");
  if (raw.length !== 32) throw new Error(`an Ed25519 public key has 32 bytes, not ${raw.length}`);
  return crypto.subtle.importKey("raw", raw, ED25519, true, ["verify"]);
}

/** Parses envelope text the way the server does (exactly one signature). */
export function parseEnvelope(text: string): Envelope {
  let data: unknown;
  try {
    data = JSON.parse(text);
  } catch {
    throw new Error("the envelope is not JSON");
  }
  const e = data as Partial<Envelope> | null;
  if (
    !e ||
    typeof e !== "object" ||
    typeof e.payload !== "string" ||
    typeof e.payloadType !== "string" ||
    !Array.isArray(e.signatures)
  ) {
    throw new Error("a DSSE envelope has payloadType, payload and signatures");
  }
  const [sig] = e.signatures;
  if (e.signatures.length !== 1 || !sig || typeof sig.sig !== "string") {
    throw new Error("the envelope must carry exactly one signature {keyid, sig}");
  }
  return e as Envelope;
}

/** Signs the PAE of `payload` with a (non-extractable) private key: the envelope as JSON text. */
export async function signEnvelope(
  payloadType: string,
  payload: Uint8Array,
  privateKey: CryptoKey,
  keyid: string,
): Promise<string> {
  const signature = new Uint8Array(await crypto.subtle.sign(ED25519, privateKey, pae(payloadType, payload)));
  return JSON.stringify({
    payloadType,
    payload: toBase64(payload),
    signatures: [{ keyid, sig: toBase64(signature) }],
  });
}

/** Whether the envelope's one signature verifies over the PAE of its payload with this key. */
export async function verifyEnvelope(envelope: Envelope, publicKey: CryptoKey): Promise<boolean> {
  const payload = fromBase64(envelope.payload, "the payload");
  const signature = fromBase64(envelope.signatures[0]!.sig, "the signature");
  return crypto.subtle.verify(ED25519, publicKey, signature, pae(envelope.payloadType, payload));
}
