/**
 * The log signer's receipts (backend approvals/receipt.py): every entry the app appended
 * carries one, signed by the log key over its origin, index, leaf hash and time. An entry
 * without a valid receipt was written behind the app's back; it is named.
 */
import { fromBase64, utf8 } from "./bytes";
import { ED25519, importPublicKey } from "./dsse";

export const RECEIPT_FORMAT = "countersign-receipt/v1";

export interface ReceiptEntry {
  index: number;
  leaf_hash: string;
  entry: string;
  receipt?: string | null;
}

function kindOf(entry: string): string {
  try {
    const data = JSON.parse(entry) as { event?: { kind?: unknown } };
    return typeof data.event?.kind === "string" ? data.event.kind : "?";
  } catch {
    return "?";
  }
}

/** Why this entry's receipt is not valid (null when it is). `leaf` is the hex leaf hash the
 * verifier computed from the entry text. */
export async function receiptProblem(row: ReceiptEntry, leaf: string, origin: string, key: CryptoKey): Promise<string | null> {
  const name = `log entry ${row.index} (${kindOf(row.entry)})`;
  if (!row.receipt) return `${name} carries no receipt from the log signer: it was not appended by the app's log signer`;
  try {
    const data = JSON.parse(row.receipt) as Record<string, unknown>;
    if (data.origin !== origin || data.index !== row.index || data.leaf !== leaf || typeof data.time !== "string") {
      return `${name} has a receipt for another entry (origin, index or leaf hash differ)`;
    }
    const message = `${RECEIPT_FORMAT}\n${origin}\n${row.index}\n${leaf}\n${data.time}\n`;
    const signature = fromBase64(String(data.signature), "the receipt signature");
    const ok = await crypto.subtle.verify(ED25519, key, signature, utf8(message));
    return ok ? null : `${name} has a receipt not signed by the log key`;
  } catch {
    return `${name} has a malformed receipt`;
  }
}

/** Problems of every entry's receipt, in log order. */
export async function receiptProblems(rows: ReceiptEntry[], leaves: string[], origin: string, publicKey: string): Promise<string[]> {
  const key = await importPublicKey(publicKey);
  const problems: string[] = [];
  for (let i = 0; i < rows.length; i++) {
    const problem = await receiptProblem(rows[i]!, leaves[i] ?? "", origin, key);
    if (problem) problems.push(problem);
  }
  return problems;
}
