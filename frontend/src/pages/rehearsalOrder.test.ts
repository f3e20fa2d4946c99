import { describe, expect, it } from "vitest";

import type { Orders } from "../editor/graph";
import { outcomeKey, pathOrder, stepPlace } from "./rehearsalOrder";

const goal = (id: string, s: string, f: string, c: string) => ({ id, next: { succeed: s, fail: f, violate: c } });

describe("rehearsal goal cards", () => {
  it("come in the order the mission is flown, not breadth first", () => {
    // The exemplar: BFS from G1 meets G2, G3, G4 before G5; a G6 reached from G1's fail
    // would come before G3 breadth first.
    const orders = {
      start: "G1",
      goals: [
        goal("G1", "G2", "G6", "G4"),
        goal("G2", "G3", "G5", "G4"),
        goal("G3", "G4", "G4", "G4"),
        goal("G4", "G5", "G5", "G5"),
        goal("G5", "COMPLETE", "ABORT", "ABORT"),
        goal("G6", "G5", "ABORT", "ABORT"),
        goal("G7", "G5", "G5", "G5"),
      ],
    } as unknown as Orders;
    const order = pathOrder(orders);
    expect(order).toEqual(["G1", "G2", "G3", "G4", "G6", "G5", "G7"]);
    // Every goal after each goal that leads to it.
    for (const g of orders.goals ?? []) {
      for (const next of Object.values((g as { next: Record<string, string> }).next)) {
        if (order.includes(next) && g.id !== "G7") expect(order.indexOf(next)).toBeGreaterThan(order.indexOf(g.id));
      }
    }
  });

  it("survives a loop and a chain longer than the call stack", () => {
    const loop = { start: "A", goals: [goal("A", "B", "B", "B"), goal("B", "A", "A", "A")] } as unknown as Orders;
    expect(pathOrder(loop)).toEqual(["A", "B"]);
    const chain = Array.from({ length: 20000 }, (_, i) => goal(`G${i}`, `G${i + 1}`, "ABORT", "ABORT"));
    expect(pathOrder({ start: "G0", goals: chain } as unknown as Orders)).toHaveLength(20000);
  });

  it("reads s, f and c as the prompt's answers", () => {
    expect(outcomeKey("s")).toBe("succeed");
    expect(outcomeKey("F")).toBe("fail");
    expect(outcomeKey("c")).toBe("violate");
    expect(outcomeKey("x")).toBeNull();
  });
});

describe("stepPlace", () => {
  it("finds a refined step's top-level goal, its unrolling marks dropped", () => {
    expect(stepPlace("G1/G1.2#3")).toEqual({ top: "G1", full: "G1/G1.2" });
    expect(stepPlace("G1/G1.2@600s/G1.2.1#1")).toEqual({ top: "G1", full: "G1/G1.2/G1.2.1" });
    expect(stepPlace("G4")).toEqual({ top: "G4", full: "G4" });
  });
});
