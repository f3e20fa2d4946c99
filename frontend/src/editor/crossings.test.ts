/**
 * the auto layout (ELK layered) against the linear layered layout it replaced
 * for up to ELK_MAX_GOALS goals, counted in edge crossings and printed for the exemplar, a
 * generated 100-goal mission and, when COUNTERSIGN_LAYOUT_ORDERS names JSON orders files
 * (tests/bench/layout_crossings.py writes Pirates there), for those too.
 */
import { describe, expect, it } from "vitest";

import exemplarText from "../../../backend/countersign/orders/examples/search-and-sample.json?raw";

import { countCrossings } from "./crossings";
import type { Orders } from "./graph";
import { elkLayout, layeredLayout } from "./layout";

/** The generated 100-goal mission of tests/e2e/test_editor_screen.py (the same rule). */
export function hundredGoals(size = 100): Orders {
  const goal = (n: number) => (n <= size ? `G${n}` : "COMPLETE");
  return {
    format: "countersign.orders/1",
    id: "hundred",
    start: "G1",
    goals: Array.from({ length: size }, (_, k) => {
      const n = k + 1;
      return { id: `G${n}`, title: `Leg ${n}`, next: { succeed: goal(n + 1), fail: goal(n + 2 + (n % 3)), violate: n % 5 === 0 ? goal(n + 7) : "ABORT" } };
    }),
    terminals: [
      { id: "COMPLETE", kind: "complete" },
      { id: "ABORT", kind: "abort" },
    ],
  } as Orders;
}

// Node's own modules, without @types/node in this browser project: only what is used here.
declare const process: { env: Record<string, string | undefined> };
const fs = (await import(/* @vite-ignore */ ["node", "fs"].join(":"))) as { readFileSync: (path: string, encoding: string) => string };

function extra(): [string, Orders][] {
  const names = process.env.COUNTERSIGN_LAYOUT_ORDERS;
  if (!names) return [];
  return names.split(":").map((p: string) => [p.split("/").pop() ?? p, JSON.parse(fs.readFileSync(p, "utf8")) as Orders]);
}

const ASPECT = 1.4; // a 1024 x 768 window's canvas, about

describe("edge crossings, ELK against the linear layered layout", () => {
  const cases: [string, Orders][] = [["exemplar", JSON.parse(exemplarText) as Orders], ["100 goals", hundredGoals()], ...extra()];
  for (const [name, orders] of cases) {
    it(`${name}: ELK crosses no more edges than the linear layout`, async () => {
      const linear = countCrossings(orders, layeredLayout(orders, ASPECT));
      const elk = countCrossings(orders, await elkLayout(orders, {}, ASPECT));
      console.log(`crossings ${name}: ELK ${elk}, linear ${linear}`);
      expect(elk).toBeLessThanOrEqual(linear);
    }, 180_000); // ELK takes seconds for 100 goals on a loaded machine: no time is asserted
  }
});
