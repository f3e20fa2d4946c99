/** Signing in the browser: this user's usable keys, and signing exactly what the server built. */
import { useKeyRing } from "../../api/keys";
import { equalBytes, fromBase64 } from "../../crypto/bytes";
import { pae, signEnvelope } from "../../crypto/dsse";
import type { StoredKey } from "../../crypto/keystore";
import { teamProblems } from "../../crypto/teamRules";
import type { Key, Prepared } from "./api";

export interface SigningKeys {
  /** Keys registered and active on the server whose private key is in this browser. */
  usable: StoredKey[];
  /** Every key in this browser for this user and server. */
  local: StoredKey[];
  /** Every key the server knows (supervisors see all supervisors' keys). */
  server: Key[];
  loading: boolean;
  error: unknown;
}

/** This user's keys; a registration or a revocation asks for them again (api/keys.ts). */
export function useSigningKeys(username: string): SigningKeys {
  const { data, error, isPending } = useKeyRing(username);
  return {
    usable: data?.usable ?? [],
    local: data?.local ?? [],
    server: data?.server ?? [],
    loading: isPending,
    error: error ?? data?.localError ?? null,
  };
}

/**
 * Signs the DSSE PAE of the statement the server prepared, after checking that the server's
 * `pae` is the PAE of its payload and that the statement says what the supervisor chose.
 */
export async function signPrepared(
  prepared: Prepared,
  key: StoredKey,
  expected: {
    digest: string;
    decision: string;
    submission?: number;
    /** What the review showed as cited: the statement must cite exactly these (none: null, []). */
    rehearsal?: string | null;
    campaigns?: string[];
    /** The fingerprint of the checks whose findings the review showed. */
    checker?: string;
    /** The orders the review showed: a team's statement must sign each member's digest. */
    orders?: unknown;
  },
): Promise<string> {
  const payload = fromBase64(prepared.payload, "the payload");
  if (!equalBytes(pae(prepared.payloadType, payload), fromBase64(prepared.pae, "the PAE"))) {
    throw new Error("The server's bytes to sign are not the DSSE PAE of its payload; nothing was signed.");
  }
  const statement = JSON.parse(new TextDecoder().decode(payload)) as Prepared["statement"];
  const digest = `sha256:${statement.subject?.[0]?.digest?.sha256 ?? ""}`;
  const predicate = statement.predicate ?? {};
  if (digest !== expected.digest) {
    throw new Error(`The statement covers ${digest}, not the reviewed orders ${expected.digest}; nothing was signed.`);
  }
  if (predicate.decision !== expected.decision) {
    throw new Error(`The statement records "${String(predicate.decision)}", not "${expected.decision}"; nothing was signed.`);
  }
  if (expected.submission !== undefined && predicate.submission !== expected.submission) {
    throw new Error("The statement is about another submission; nothing was signed.");
  }
  if (predicate.key_id !== key.keyId) throw new Error("The statement names another key; nothing was signed.");
  if (expected.rehearsal !== undefined && (predicate.rehearsal_digest ?? null) !== expected.rehearsal) {
    throw new Error("The statement cites another rehearsal record than the review showed; nothing was signed.");
  }
  if (expected.checker !== undefined && predicate.checker !== expected.checker) {
    throw new Error("The statement signs a report made by other checks than the review showed: reload the review; nothing was signed.");
  }
  if (expected.campaigns !== undefined) {
    const signed = Array.isArray(predicate.campaigns) ? [...(predicate.campaigns as string[])].sort() : [];
    const shown = [...expected.campaigns].sort();
    if (signed.length !== shown.length || signed.some((d, i) => d !== shown[i])) {
      throw new Error("The statement cites other rehearsal campaigns than the review showed; nothing was signed.");
    }
  }
  if (expected.orders !== undefined) {
    const problems = await teamProblems(expected.orders, predicate);
    if (problems.length) {
      throw new Error(`The statement's team members disagree with the reviewed orders: ${problems.join("; ")}; nothing was signed.`);
    }
  }
  return signEnvelope(prepared.payloadType, payload, key.keyPair.privateKey, key.keyId);
}
