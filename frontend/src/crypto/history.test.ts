/** Finding 3 in the browser: after one checkpoint, a truncated, rewritten or forked log is
 * caught, naming both heads; a consistent extension is accepted and kept. */
import { describe, expect, it } from "vitest";

import { toHex, utf8 } from "./bytes";
import { checkHistory, loadHead } from "./history";
import { leafHash, nodeHash, verifyConsistency } from "./merkle";

class Memory {
  map = new Map<string, string>();
  getItem(k: string) {
    return this.map.get(k) ?? null;
  }
  setItem(k: string, v: string) {
    this.map.set(k, v);
  }
  removeItem(k: string) {
    this.map.delete(k);
  }
}

async function leaves(items: string[]): Promise<Uint8Array[]> {
  return Promise.all(items.map((i) => leafHash(utf8(i))));
}

// Trees of 2, 3 and 4 leaves with their RFC 6962 roots and consistency proofs.
async function world(items: string[]) {
  const [a, b, c, d] = await leaves(items);
  const ab = await nodeHash(a!, b!);
  const cd = await nodeHash(c!, d!);
  return {
    root2: ab,
    root3: await nodeHash(ab, c!),
    root4: await nodeHash(ab, cd),
    proof2to4: [cd],
    proof3to4: [c!, d!, ab],
  };
}

describe("one history per log", () => {
  it("keeps a consistent extension and names both heads of a rollback or fork", async () => {
    const honest = await world(["a", "b", "c", "d"]);
    expect(await verifyConsistency(2, 4, honest.proof2to4, honest.root2, honest.root4)).toBe(true);
    const storage = new Memory();
    const key = "countersign.checkpoint:https://app.example:log.example/1";
    const three = { size: 3, root: toHex(honest.root3) };
    const first = await checkHistory(storage, key, three, () => Promise.reject(new Error("not asked")));
    expect(first.problem).toBeNull();
    expect(loadHead(storage, key)).toEqual(three);

    const four = { size: 4, root: toHex(honest.root4) };
    const proofs = (first_: number, second: number) => {
      expect([first_, second]).toEqual([3, 4]);
      return Promise.resolve({ hashes: honest.proof3to4.map(toHex) });
    };
    expect((await checkHistory(storage, key, four, proofs)).problem).toBeNull();
    expect(loadHead(storage, key)).toEqual(four);

    const truncated = { size: 3, root: toHex(honest.root3) };
    expect((await checkHistory(storage, key, truncated, proofs)).problem).toBe(
      `the log was rolled back (truncated): a checkpoint seen before has size 4, root ${four.root}; the server now presents size 3, root ${truncated.root}`,
    );
    const other = await world(["a", "b", "X", "d"]);
    const forked = { size: 4, root: toHex(other.root4) };
    expect((await checkHistory(storage, key, forked, proofs)).problem).toBe(
      `the log forks: a checkpoint seen before has size 4, root ${four.root}; the server now presents size 4, root ${forked.root}`,
    );
    expect(loadHead(storage, key)).toEqual(four); // nothing inconsistent is kept

    // A rewritten log that grew: the server's proof does not lead from the kept head.
    const rewritten = new Memory();
    await checkHistory(rewritten, key, { size: 2, root: toHex(honest.root2) }, proofs);
    const changed = await world(["a", "Y", "c", "d"]);
    const grown = { size: 4, root: toHex(changed.root4) };
    const problem = (await checkHistory(rewritten, key, grown, () => Promise.resolve({ hashes: changed.proof2to4.map(toHex) }))).problem;
    expect(problem).toBe(
      `the log forks from the checkpoint seen before (size 2, root ${toHex(honest.root2)}): no valid consistency proof to size 4, root ${grown.root}`,
    );
  });
});
