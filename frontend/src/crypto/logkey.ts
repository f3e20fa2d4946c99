/**
 * The log key the auditor trusts, pinned in this browser (the auditor must not have to
 * trust the server). Checkpoints are verified against the key the server sends; that proves
 * nothing if the server can send any key. So the auditor pins the log's public key once per
 * server origin, on first use after comparing it with the published key or by entering the
 * published key (the one `countersign audit verify --log-key` takes), and every later
 * verification checks that the server still presents that key.
 *
 * Pure functions over a small storage interface (localStorage in the app, a Map in tests).
 */
import { fromBase64, toBase64 } from "./bytes";
import { keyId } from "./dsse";
import { fingerprint } from "./keystore";
import type { Check } from "./verify";

/** The part of the Web Storage API the pin needs (`window.localStorage` satisfies it). */
export interface PinStorage {
  getItem(key: string): string | null;
  setItem(key: string, value: string): void;
  removeItem(key: string): void;
}

export interface LogKey {
  /** standard base64 of the raw 32-byte Ed25519 public key */
  publicKey: string;
  /** hex SHA-256 of the raw public key, computed here (never taken from the server) */
  keyId: string;
}

export type PinSource = "first use" | "entered";

export interface PinnedLogKey extends LogKey {
  origin: string;
  pinnedAt: string;
  source: PinSource;
}

export interface StoredPin {
  pinned: PinnedLogKey | null;
  /** why a pin stored for this origin cannot be used (it then counts as a mismatch) */
  problem: string | null;
}

export type PinState =
  | { kind: "unpinned"; presented: LogKey }
  | { kind: "matches"; pinned: PinnedLogKey; presented: LogKey }
  | { kind: "differs"; pinned: PinnedLogKey; presented: LogKey }
  | { kind: "unusable"; problem: string };

const PREFIX = "countersign.log-key-pin|";
// DER prefix of an Ed25519 SubjectPublicKeyInfo (RFC 8410): SEQUENCE, AlgorithmIdentifier
// 1.3.101.112, BIT STRING of 33 bytes; the raw key follows.
const SPKI_PREFIX = [0x30, 0x2a, 0x30, 0x05, 0x06, 0x03, 0x2b, 0x65, 0x70, 0x03, 0x21, 0x00];

export function pinStorageKey(origin: string): string {
  return `${PREFIX}${origin}`;
}

function rawKey(bytes: Uint8Array<ArrayBuffer>): Uint8Array<ArrayBuffer> {
  if (bytes.length === 32) return bytes;
  if (bytes.length === 44 && SPKI_PREFIX.every((b, i) => bytes[i] === b)) return bytes.slice(12);
  throw new Error(
    `an Ed25519 log key has 32 bytes (or 44 as a SubjectPublicKeyInfo), not ${bytes.length}`,
  );
}

/** A log key as the auditor may paste it: the base64 of the raw 32-byte key (as
 * `countersign audit verify --log-key` and the checkpoint's `public_key` give it), or a PEM
 * `PUBLIC KEY` (`openssl pkey -pubout`). Whitespace is ignored; throws on anything else. */
export async function parseLogKey(text: string): Promise<LogKey> {
  let body = text.trim();
  const pem = /^-----BEGIN PUBLIC KEY-----([\s\S]*)-----END PUBLIC KEY-----$/.exec(body);
  if (pem) body = pem[1]!;
  else if (body.startsWith("-----")) throw new Error("only a PEM PUBLIC KEY block is accepted");
  body = body.replace(/\s+/g, "");
  if (!body) throw new Error("enter the log's public key");
  const raw = rawKey(fromBase64(body, "the log key"));
  return { publicKey: toBase64(raw), keyId: await keyId(raw) };
}

/** The pin kept for this server origin, checked again (its key id is recomputed). */
export async function loadPin(storage: PinStorage, origin: string): Promise<StoredPin> {
  const text = storage.getItem(pinStorageKey(origin));
  if (text === null) return { pinned: null, problem: null };
  try {
    const data = JSON.parse(text) as Partial<PinnedLogKey> | null;
    if (!data || typeof data.publicKey !== "string") throw new Error("it names no public key");
    const key = await parseLogKey(data.publicKey);
    if (data.keyId !== undefined && data.keyId !== key.keyId) throw new Error("its key id is not the hash of its key");
    if (data.origin !== undefined && data.origin !== origin) throw new Error(`it belongs to ${String(data.origin)}`);
    return {
      pinned: {
        ...key,
        origin,
        pinnedAt: typeof data.pinnedAt === "string" ? data.pinnedAt : "",
        source: data.source === "entered" ? "entered" : "first use",
      },
      problem: null,
    };
  } catch (e) {
    return { pinned: null, problem: `the log key pinned in this browser cannot be read (${(e as Error).message})` };
  }
}

/** Pins `text` (a log key in any form `parseLogKey` reads) for `origin`, replacing any pin. */
export async function pinLogKey(
  storage: PinStorage,
  origin: string,
  text: string,
  source: PinSource,
  now: Date = new Date(),
): Promise<PinnedLogKey> {
  const key = await parseLogKey(text);
  const pinned: PinnedLogKey = { ...key, origin, pinnedAt: now.toISOString(), source };
  storage.setItem(pinStorageKey(origin), JSON.stringify(pinned));
  return pinned;
}

export function forgetPin(storage: PinStorage, origin: string): void {
  storage.removeItem(pinStorageKey(origin));
}

/** How the key the server presents (the checkpoint's `public_key`) relates to the pin. */
export async function comparePin(stored: StoredPin, presentedKey: string): Promise<PinState> {
  let presented: LogKey;
  try {
    presented = await parseLogKey(presentedKey);
  } catch (e) {
    return { kind: "unusable", problem: `the server's log key is unusable: ${(e as Error).message}` };
  }
  if (stored.problem !== null) return { kind: "unusable", problem: stored.problem };
  if (stored.pinned === null) return { kind: "unpinned", presented };
  const kind = stored.pinned.keyId === presented.keyId ? "matches" : "differs";
  return { kind, pinned: stored.pinned, presented };
}

export const PIN_LABEL = "Log key matches the pinned key";

/** The verification check of the pin; null while no key is pinned (the page asks to pin). */
export function pinCheck(state: PinState): Check | null {
  switch (state.kind) {
    case "unpinned":
      return null;
    case "unusable":
      return { id: "pin", label: PIN_LABEL, ok: false, detail: state.problem };
    case "matches":
      return {
        id: "pin",
        label: PIN_LABEL,
        ok: true,
        detail: `the checkpoint is signed by log key ${fingerprint(state.presented.keyId)}, the key pinned in this browser${
          state.pinned.pinnedAt ? ` on ${state.pinned.pinnedAt.slice(0, 10)}` : ""
        }`,
      };
    case "differs":
      return {
        id: "pin",
        label: PIN_LABEL,
        ok: false,
        detail:
          `the server presents log key ${fingerprint(state.presented.keyId)}, but this browser pinned log key ` +
          `${fingerprint(state.pinned.keyId)}: the server's key changed, or this is not the log you pinned`,
      };
  }
}
