/**
 * The browser holds the server to one history: it keeps the last checkpoint it verified, per
 * server origin and log origin, and requires a consistency proof from it to every newer one.
 * A rollback (smaller size) or a fork (same size, other root; or no valid proof) is reported
 * naming both tree heads.
 */
import { fromHex } from "./bytes";
import { verifyConsistency } from "./merkle";
import type { PinStorage } from "./logkey";

export interface Head {
  size: number;
  root: string; // hex
}

export interface ConsistencyProof {
  hashes: string[];
}

export function historyStorageKey(serverOrigin: string, logOrigin: string): string {
  return `countersign.checkpoint:${serverOrigin}:${logOrigin}`;
}

export function describe(head: Head): string {
  return `size ${head.size}, root ${head.root.toLowerCase()}`;
}

export function loadHead(storage: PinStorage, key: string): Head | null {
  try {
    const data = JSON.parse(storage.getItem(key) ?? "null") as Head | null;
    return data && Number.isSafeInteger(data.size) && typeof data.root === "string" ? data : null;
  } catch {
    return null;
  }
}

/** Compare the checkpoint with the one kept; keep it when it continues the history. Returns
 * the problem (naming both heads) or null. `proof(first, second)` fetches a consistency proof. */
export async function checkHistory(
  storage: PinStorage,
  key: string,
  head: Head,
  proof: (first: number, second: number) => Promise<ConsistencyProof>,
): Promise<{ problem: string | null; seen: Head | null }> {
  const seen = loadHead(storage, key);
  let problem: string | null = null;
  if (seen) {
    if (head.size < seen.size) {
      problem = `the log was rolled back (truncated): a checkpoint seen before has ${describe(seen)}; the server now presents ${describe(head)}`;
    } else if (head.size === seen.size && head.root.toLowerCase() !== seen.root.toLowerCase()) {
      problem = `the log forks: a checkpoint seen before has ${describe(seen)}; the server now presents ${describe(head)}`;
    } else if (head.size > seen.size && seen.size > 0) {
      let ok = false;
      try {
        const p = await proof(seen.size, head.size);
        ok = await verifyConsistency(seen.size, head.size, p.hashes.map((h) => fromHex(h, "a proof hash")), fromHex(seen.root), fromHex(head.root));
      } catch {
        ok = false;
      }
      if (!ok) problem = `the log forks from the checkpoint seen before (${describe(seen)}): no valid consistency proof to ${describe(head)}`;
    }
  }
  if (problem === null) storage.setItem(key, JSON.stringify({ size: head.size, root: head.root.toLowerCase() }));
  return { problem, seen };
}
