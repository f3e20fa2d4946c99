/**
 * Verifies one approval in the browser, trusting nothing the server says about validity: the
 * DSSE signature against the supervisor's key that was valid when the approval was logged, the
 * log's hash chain and Merkle root against the signed checkpoint, the inclusion proof of the
 * approval's log entry, and the digest of the orders as approved. Every check reports a
 * sentence; a failing one names the log entry it concerns.
 */
import { fromBase64, fromHex, fromUtf8, sha256Hex, toBase64, toHex, utf8 } from "./bytes";
import { jsonDigest } from "./canonical";
import { ED25519, importPublicKey, keyId, parseEnvelope, PAYLOAD_TYPE, verifyEnvelope } from "./dsse";
import { checkLog } from "./logRules";
import { leafHash, rootOf, verifyInclusion } from "./merkle";
import { receiptProblems } from "./receipts";
import { type ApprovalRow, checkRecords } from "./recordRules";
import { isTeamApproval, teamProblems } from "./teamRules";

export const GENESIS = "0".repeat(64);

/** The first three problems and how many more: a check's detail line stays readable. */
function firstProblems(problems: string[]): string {
  const more = problems.length > 3 ? ` (and ${problems.length - 3} more)` : "";
  return problems.slice(0, 3).join("; ") + more;
}

export interface Checkpoint {
  size: number;
  root: string;
  note: string;
  key_id: string;
  public_key: string;
  signature: string;
}

export interface InclusionProof {
  index: number;
  size: number;
  hashes: string[];
}

export interface LogEntryRow {
  index: number;
  leaf_hash: string;
  entry: string;
  receipt?: string | null;
}

export interface ApprovalRecord {
  id: number;
  mission: string;
  version: number;
  decision: string;
  digest: string;
  log_index: number | null;
  envelope: string;
  orders: unknown;
  key: { key_id: string; public_key: string; user: string | null };
  checkpoint: Checkpoint;
  inclusion: InclusionProof | null;
}

export interface Check {
  id: "pin" | "history" | "receipts" | "checkpoint" | "chain" | "root" | "rules" | "records" | "inclusion" | "logged" | "key" | "signature" | "statement" | "orders" | "team";
  label: string;
  ok: boolean;
  detail: string;
}

interface SignedStatement {
  subject?: { name?: string; digest?: Record<string, string> }[];
  predicate?: Record<string, unknown>;
}

interface LogEvent {
  kind?: string;
  actor?: unknown;
  detail?: Record<string, unknown>;
}

/** A C2SP tlog-checkpoint body: the log's origin line, its size and base64 root. */
export function checkpointNote(origin: string, size: number, root: Uint8Array): string {
  return `${origin}\n${size}\n${toBase64(root)}\n`;
}

/** The origin line of a checkpoint body (unique to the log). */
export function checkpointOrigin(note: string): string {
  return note.split("\n", 1)[0] ?? "";
}

/** The checkpoint's Ed25519 signature over its note, which must state its size and root. */
export async function verifyCheckpoint(checkpoint: Checkpoint): Promise<string | null> {
  let root: Uint8Array;
  try {
    root = fromHex(checkpoint.root, "the checkpoint root");
  } catch (e) {
    return (e as Error).message;
  }
  const origin = checkpointOrigin(checkpoint.note);
  if (!origin || checkpoint.note !== checkpointNote(origin, checkpoint.size, root)) {
    return `the checkpoint note does not state size ${checkpoint.size} and its root`;
  }
  try {
    const raw = fromBase64(checkpoint.public_key, "the log key");
    if ((await keyId(raw)) !== checkpoint.key_id) return "the log key does not match its key id";
    const key = await importPublicKey(checkpoint.public_key);
    const signature = fromBase64(checkpoint.signature, "the checkpoint signature");
    const ok = await crypto.subtle.verify(ED25519, key, signature, utf8(checkpoint.note));
    return ok ? null : `the checkpoint at size ${checkpoint.size} is not signed by the log key`;
  } catch (e) {
    return (e as Error).message;
  }
}

function parseEntry(text: string): { index?: unknown; prev?: unknown; event?: LogEvent } | null {
  try {
    const data = JSON.parse(text) as unknown;
    return data && typeof data === "object" ? (data as { index?: unknown; prev?: unknown; event?: LogEvent }) : null;
  } catch {
    return null;
  }
}

/** Leaf hashes of the entries, and what is wrong with the chain (empty when nothing). */
export async function checkChain(entries: LogEntryRow[]): Promise<{ leaves: Uint8Array[]; events: LogEvent[]; problems: string[] }> {
  const leaves: Uint8Array[] = [];
  const events: LogEvent[] = [];
  const problems: string[] = [];
  let prev = GENESIS;
  for (let i = 0; i < entries.length; i++) {
    const row = entries[i]!;
    const leaf = await leafHash(utf8(row.entry));
    const hex = toHex(leaf);
    leaves.push(leaf);
    const entry = parseEntry(row.entry);
    if (row.index !== i) problems.push(`the server sent entry ${row.index} where entry ${i} belongs`);
    if (!entry || typeof entry.event !== "object" || entry.event === null) {
      problems.push(`log entry ${i} is not a valid entry`);
      events.push({});
    } else {
      events.push(entry.event);
      if (entry.index !== i) problems.push(`log entry ${i} claims index ${String(entry.index)}`);
      if (entry.prev !== prev) {
        problems.push(
          `log entry ${i} does not chain to entry ${i - 1}: entry ${i - 1} was changed or removed, or entry ${i} was altered`,
        );
      }
    }
    if (row.leaf_hash !== hex) problems.push(`log entry ${i} does not hash to the leaf hash recorded for it: it was changed`);
    prev = hex;
  }
  return { leaves, events, problems };
}

function keyHistory(events: LogEvent[], keyIdWanted: string): { registered: number | null; publicKey: unknown; revoked: number | null } {
  let registered: number | null = null;
  let publicKey: unknown = null;
  let revoked: number | null = null;
  events.forEach((event, index) => {
    const detail = event.detail ?? {};
    if (detail.key_id !== keyIdWanted) return;
    if (event.kind === "key.registered" && registered === null) {
      registered = index;
      publicKey = detail.public_key;
    } else if (event.kind === "key.revoked" && revoked === null) {
      revoked = index;
    }
  });
  return { registered, publicKey, revoked };
}

function fail(id: Check["id"], label: string, detail: string): Check {
  return { id, label, ok: false, detail };
}

/** Every check of one approval, in the order they are shown. `entries` are the log's first
 * `checkpoint.size` entries as fetched from the server (or more, up to the approval's own
 * entry: every one must carry a receipt of the log signer). `rows`, when given, are every
 * approval record the server lists for the record's mission: each must agree with the log. */
export async function verifyApproval(record: ApprovalRecord, all: LogEntryRow[], rows?: ApprovalRow[]): Promise<Check[]> {
  const entries = all.slice(0, record.checkpoint.size);
  const checks: Check[] = [];
  const cp = record.checkpoint;
  const index = record.log_index;
  const entryName = index === null ? "its log entry" : `log entry ${index}`;

  const checkpointProblem = await verifyCheckpoint(cp);
  checks.push({
    id: "checkpoint",
    label: "Checkpoint signed by the log key",
    ok: checkpointProblem === null,
    detail: checkpointProblem ?? `size ${cp.size}, log key ${cp.key_id.slice(0, 16)}…`,
  });

  const { leaves, events, problems } = await checkChain(all);
  leaves.splice(record.checkpoint.size);
  let receiptIssues: string[];
  try {
    const allLeaves = await Promise.all(all.map(async (r) => toHex(await leafHash(utf8(r.entry)))));
    receiptIssues = await receiptProblems(all, allLeaves, checkpointOrigin(cp.note), cp.public_key);
  } catch (e) {
    receiptIssues = [(e as Error).message];
  }
  checks.push({
    id: "receipts",
    label: "Every log entry carries the log signer's receipt",
    ok: receiptIssues.length === 0,
    detail: receiptIssues.length
      ? firstProblems(receiptIssues)
      : `${all.length} entries, each receipted by the log key`,
  });
  if (entries.length !== cp.size) {
    problems.unshift(`the server sent ${entries.length} log entries, but the checkpoint covers ${cp.size}`);
  }
  checks.push({
    id: "chain",
    label: "Hash chain of the log",
    ok: problems.length === 0,
    detail: problems.length
      ? firstProblems(problems)
      : `${entries.length} entries, each chained to the one before`,
  });

  let rootOk = false;
  try {
    rootOk = toHex(await rootOf(leaves)) === cp.root.toLowerCase();
  } catch {
    rootOk = false;
  }
  checks.push({
    id: "root",
    label: "Log matches the signed checkpoint",
    ok: rootOk,
    detail: rootOk
      ? `the RFC 6962 root of entries 0..${cp.size - 1} is the signed root`
      : `log entries 0..${cp.size - 1} differ from what the checkpoint at size ${cp.size} signed (an entry in that range was changed)`,
  });

  // --- log-wide rules, logRules.ts ---
  const ruleProblems = checkLog(events);
  checks.push({
    id: "rules",
    label: "The log describes a legal history",
    ok: ruleProblems.length === 0,
    detail: ruleProblems.length
      ? firstProblems(ruleProblems)
      : "one decision per submission, one active submission per version, no signature by a revoked key",
  });
  // --- end of the log-wide rules ---
  if (rows) {
    // Finding 5: a deleted revocation (or decision) row, caught from the log.
    const recordProblems = checkRecords(events, record.mission, record.id, rows);
    checks.push({
      id: "records",
      label: "The server's approval records agree with the log",
      ok: recordProblems.length === 0,
      detail: recordProblems.length
        ? firstProblems(recordProblems)
        : `every decision the log holds on ${record.mission} has its record, and every logged revocation of this approval is shown`,
    });
  }

  const proof = record.inclusion;
  if (index === null || !proof || index >= leaves.length) {
    checks.push(fail("inclusion", "Inclusion in the log", `${entryName} is not covered by the checkpoint`));
  } else {
    let included = false;
    try {
      included =
        proof.index === index &&
        proof.size === cp.size &&
        (await verifyInclusion(leaves[index]!, index, cp.size, proof.hashes.map((h) => fromHex(h, "a proof hash")), fromHex(cp.root)));
    } catch {
      included = false;
    }
    checks.push({
      id: "inclusion",
      label: `Inclusion of ${entryName} in the log`,
      ok: included,
      detail: included
        ? `the inclusion proof (${proof.hashes.length} hashes) leads to the signed root of size ${cp.size}`
        : `the inclusion proof of ${entryName} does not verify against the signed checkpoint`,
    });
  }

  const event = index !== null ? events[index] : undefined;
  const detail = event?.detail ?? {};
  const envelopeDigest = `sha256:${await sha256Hex(utf8(record.envelope))}`;
  const loggedProblems: string[] = [];
  if (!event || event.kind !== `approval.${record.decision}`) {
    loggedProblems.push(`${entryName} does not record this ${record.decision} decision`);
  } else {
    if (detail.envelope_digest !== envelopeDigest) {
      loggedProblems.push(`the envelope differs from the one logged in ${entryName}`);
    }
    if (detail.orders_digest !== record.digest) {
      loggedProblems.push(`the orders digest differs from the one logged in ${entryName}`);
    }
  }
  checks.push({
    id: "logged",
    label: `Envelope recorded in ${entryName}`,
    ok: loggedProblems.length === 0,
    detail: loggedProblems.length ? loggedProblems.join("; ") : `its SHA-256 ${envelopeDigest.slice(0, 23)}… is the logged one`,
  });

  let publicKey: CryptoKey | null = null;
  const keyProblems: string[] = [];
  try {
    const envelope = parseEnvelope(record.envelope);
    const kid = envelope.signatures[0]!.keyid ?? "";
    if (kid !== record.key.key_id) keyProblems.push(`the envelope names key ${kid}, not ${record.key.key_id}`);
    const raw = fromBase64(record.key.public_key, "the public key");
    if ((await keyId(raw)) !== record.key.key_id) keyProblems.push(`key ${record.key.key_id} does not hash to its id`);
    const history = keyHistory(events, record.key.key_id);
    if (history.registered === null || index === null || history.registered > index) {
      keyProblems.push(`key ${record.key.key_id.slice(0, 16)}… was not registered in the log before ${entryName}`);
    } else if (history.publicKey !== record.key.public_key) {
      keyProblems.push(`key ${record.key.key_id.slice(0, 16)}… differs from its registration in log entry ${history.registered}`);
    }
    if (history.revoked !== null && index !== null && history.revoked < index) {
      keyProblems.push(`key ${record.key.key_id.slice(0, 16)}… was revoked (log entry ${history.revoked}) before it signed`);
    }
    publicKey = await importPublicKey(record.key.public_key);
  } catch (e) {
    keyProblems.push((e as Error).message);
  }
  checks.push({
    id: "key",
    label: "Signing key valid at signing time",
    ok: keyProblems.length === 0,
    detail: keyProblems.length
      ? keyProblems.join("; ")
      : `${record.key.user ?? "the supervisor"}'s key ${record.key.key_id.slice(0, 16)}…, registered in the log before ${entryName} and not revoked before it`,
  });

  let statement = null as SignedStatement | null;
  try {
    const envelope = parseEnvelope(record.envelope);
    if (envelope.payloadType !== PAYLOAD_TYPE) throw new Error(`the payloadType must be ${PAYLOAD_TYPE}`);
    if (!publicKey) throw new Error("there is no usable public key to check it with");
    const ok = await verifyEnvelope(envelope, publicKey);
    if (!ok) throw new Error(`the signature does not verify over the DSSE PAE of the payload (${entryName})`);
    statement = JSON.parse(fromUtf8(fromBase64(envelope.payload, "the payload"))) as SignedStatement;
    checks.push({ id: "signature", label: "DSSE signature (Ed25519)", ok: true, detail: "valid over the DSSE PAE of the payload" });
  } catch (e) {
    checks.push(fail("signature", "DSSE signature (Ed25519)", (e as Error).message));
  }

  if (!statement) {
    checks.push(fail("statement", "Signed statement matches the record", "there is no verified statement to compare"));
  } else {
    const problems: string[] = [];
    const signed = `sha256:${statement.subject?.[0]?.digest?.sha256 ?? ""}`;
    const p = statement.predicate ?? {};
    if (signed !== record.digest) problems.push(`it signs ${signed}, not ${record.digest}`);
    if (p.decision !== record.decision) problems.push(`it signs the decision ${String(p.decision)}, not ${record.decision}`);
    if (p.mission !== record.mission || p.version !== record.version) problems.push("it names another mission or version");
    if (record.key.user !== null && p.supervisor !== record.key.user) {
      problems.push(`signed with ${record.key.user}'s key but names ${String(p.supervisor)}`);
    }
    checks.push({
      id: "statement",
      label: "Signed statement matches the record",
      ok: problems.length === 0,
      detail: problems.length ? problems.join("; ") : `${record.decision} ${record.mission}@v${record.version} by ${String(p.supervisor)}`,
    });
  }

  if (record.decision === "revoked") {
    checks.push({ id: "orders", label: "Orders as approved", ok: true, detail: "a revocation covers the orders of the approval it revokes" });
  } else {
    let digest = "";
    try {
      digest = await jsonDigest(record.orders);
    } catch {
      digest = "";
    }
    const ok = digest === record.digest;
    checks.push({
      id: "orders",
      label: "Orders as approved hash to the signed digest",
      ok,
      detail: ok
        ? `RFC 8785 SHA-256 ${digest.slice(0, 23)}…`
        : `the stored orders of ${record.mission}@v${record.version} do not hash to the signed digest ${record.digest}`,
    });
    // A team's approval also signs each member's digest: single-vehicle approvals get no check.
    if (statement && isTeamApproval(record.orders, statement.predicate)) {
      const problems = await teamProblems(record.orders, statement.predicate);
      const members = Object.keys((statement.predicate?.team ?? {}) as object);
      checks.push({
        id: "team",
        label: "Each team member's orders hash to its signed digest",
        ok: problems.length === 0,
        detail: problems.length ? firstProblems(problems) : `${members.length} members: ${members.join(", ")}`,
      });
    }
  }
  return checks;
}
