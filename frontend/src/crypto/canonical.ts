/**
 * RFC 8785 (JCS) canonical JSON of data parsed by JSON.parse: object keys sorted by UTF-16 code
 * units, no whitespace, strings and numbers written as ECMAScript's JSON.stringify writes them
 * (which is what RFC 8785 specifies). The orders digest is SHA-256 over these bytes.
 */
import { sha256Hex, utf8 } from "./bytes";

export function canonicalJson(value: unknown): string {
  if (value === null || typeof value === "boolean" || typeof value === "string") {
    return JSON.stringify(value);
  }
  if (typeof value === "number") {
    if (!Number.isFinite(value)) throw new Error("JSON has no NaN or Infinity");
    return JSON.stringify(value);
  }
  if (Array.isArray(value)) return `[${value.map(canonicalJson).join(",")}]`;
  if (typeof value === "object") {
    const entries = Object.entries(value as Record<string, unknown>)
      .filter(([, v]) => v !== undefined)
      .sort(([a], [b]) => (a < b ? -1 : a > b ? 1 : 0));
    return `{${entries.map(([k, v]) => `${JSON.stringify(k)}:${canonicalJson(v)}`).join(",")}}`;
  }
  throw new Error(`cannot canonicalise a ${typeof value}`);
}

/** `sha256:<hex>` of the canonical JSON, as the server's orders and statement digests. */
export async function jsonDigest(value: unknown): Promise<string> {
  return `sha256:${await sha256Hex(utf8(canonicalJson(value)))}`;
}
