import { describe, expect, it } from "vitest";

import {
  addGoal,
  addTerminal,
  checkConnection,
  connect,
  deleteNodes,
  describeDifferences,
  disconnect,
  markersBySubject,
  ordersToGraph,
  parseEnvelope,
  envelopeToText,
  type Orders,
  toggleScope,
  addConstraint,
} from "./graph";
import { canRedo, canUndo, createHistory, push, redo, undo } from "./history";
import { autoLayout, GOAL_SIZE, layeredLayout, TERMINAL_SIZE } from "./layout";

const base: Orders = {
  format: "countersign.orders/1",
  id: "m",
  start: "G1",
  goals: [
    { id: "G1", title: "Search", next: { succeed: "G2", fail: "ABORT" } },
    { id: "G2", title: "Sample", next: { succeed: "COMPLETE", fail: "ABORT", violate: "NOWHERE" } },
  ],
};

describe("orders -> graph", () => {
  it("makes a node per goal and terminal and an edge per outcome target", () => {
    const { nodes, edges } = ordersToGraph(base, { G1: { x: 5, y: 6 } });
    expect(nodes.map((n) => [n.id, n.kind])).toEqual([
      ["G1", "goal"],
      ["G2", "goal"],
      ["COMPLETE", "terminal"],
      ["ABORT", "terminal"],
    ]);
    expect(nodes[0]?.position).toEqual({ x: 5, y: 6 });
    expect(nodes[0]?.start).toBe(true);
    expect(edges.map((e) => e.id)).toEqual(["G1:succeed:G2", "G1:fail:ABORT", "G2:succeed:COMPLETE", "G2:fail:ABORT", "G2:violate:NOWHERE"]);
    expect(edges.find((e) => e.target === "NOWHERE")?.dangling).toBe(true);
  });
});

describe("connections", () => {
  it("allows one successor per outcome", () => {
    expect(checkConnection(base, "G1", "violate", "COMPLETE").ok).toBe(true);
    const taken = checkConnection(base, "G1", "succeed", "COMPLETE");
    expect(taken.ok).toBe(false);
    expect(taken.reason).toMatch(/already has a successor/);
  });
  it("refuses connections from terminals, to unknown nodes, or without an outcome", () => {
    expect(checkConnection(base, "ABORT", "succeed", "G1").ok).toBe(false);
    expect(checkConnection(base, "G1", "violate", "G9").ok).toBe(false);
    expect(checkConnection(base, "G1", "in", "G2").ok).toBe(false);
  });
  it("connects and disconnects", () => {
    const { orders, check } = connect(base, "G1", "violate", "G1");
    expect(check.ok).toBe(true);
    expect(orders.goals?.[0]?.next?.violate).toBe("G1");
    expect(base.goals?.[0]?.next?.violate).toBeUndefined();
    const back = disconnect(orders, "G1", "violate", "G1");
    expect(back.goals?.[0]?.next).toEqual({ succeed: "G2", fail: "ABORT" });
  });
});

describe("edits", () => {
  it("adds goals with fresh ids; the first goal becomes the start", () => {
    const empty: Orders = { id: "e", goals: [] };
    const one = addGoal(empty);
    expect(one.id).toBe("G1");
    expect(one.orders.start).toBe("G1");
    const two = addGoal(one.orders);
    expect(two.id).toBe("G2");
    expect(two.orders.start).toBe("G1");
  });
  it("adds terminals with unique ids", () => {
    const { id, orders } = addTerminal(base, "abort");
    expect(id).toBe("ABORT2");
    expect(orders.terminals?.map((t) => t.id)).toEqual(["COMPLETE", "ABORT", "ABORT2"]);
  });
  it("deletes nodes with their incoming edges, scopes and start", () => {
    let orders: Orders = { ...base, constraints: [{ id: "C1", applies_to: ["G1", "G2"] }] };
    orders = deleteNodes(orders, ["G2"]);
    expect(orders.goals?.map((g) => g.id)).toEqual(["G1"]);
    expect(orders.goals?.[0]?.next).toEqual({ fail: "ABORT" });
    expect(orders.constraints?.[0]?.applies_to).toEqual(["G1"]);
    orders = deleteNodes(orders, ["G1", "ABORT"]);
    expect(orders.start).toBeNull();
    expect(orders.terminals?.map((t) => t.id)).toEqual(["COMPLETE"]);
  });
  it("toggles constraint scopes", () => {
    const { orders, id } = addConstraint(base);
    expect(id).toBe("C1");
    const scoped = toggleScope(orders, id, "G2");
    expect(scoped.constraints?.[0]?.applies_to).toEqual(["G2"]);
    expect(toggleScope(scoped, id, "G2").constraints?.[0]?.applies_to).toEqual([]);
  });
  it("reads and writes envelopes as lines", () => {
    expect(parseEnvelope("depth_m 25 50\n\nspeed 0, 2")).toEqual({ envelope: { depth_m: [25, 50], speed: [0, 2] } });
    expect(parseEnvelope("depth_m 50 25").error).toMatch(/above/);
    expect(parseEnvelope("depth_m x").error).toMatch(/Line 1/);
    expect(envelopeToText({ depth_m: [25, 50] })).toBe("depth_m 25 50");
  });
  it("marks findings on their subjects, errors first", () => {
    const markers = markersBySubject([
      { code: "G10", severity: "warning", subjects: ["G3"] },
      { code: "G7", severity: "error", subjects: ["G1", "G3"] },
    ]);
    expect(markers.get("G3")).toEqual({ codes: ["G10", "G7"], severity: "error" });
    expect(markers.get("G1")?.codes).toEqual(["G7"]);
  });
  it("describes the differences for the conflict dialog", () => {
    const theirs = addGoal(base).orders;
    const mine = { ...base, title: "New" };
    expect(describeDifferences(mine, theirs)).toEqual(['Title: yours "New", theirs "".', "Goal G3: only in theirs."]);
    expect(describeDifferences(base, base)).toEqual([]);
  });
});

describe("undo/redo", () => {
  it("undoes and redoes and drops the redo branch on a new edit", () => {
    let h = createHistory(1);
    h = push(h, 2);
    h = push(h, 3);
    expect(canUndo(h)).toBe(true);
    h = undo(h);
    expect(h.present).toBe(2);
    expect(canRedo(h)).toBe(true);
    h = redo(h);
    expect(h.present).toBe(3);
    h = undo(undo(h));
    expect(h.present).toBe(1);
    h = push(h, 9);
    expect(canRedo(h)).toBe(false);
    expect(undo(undo(h)).present).toBe(1);
  });
  it("coalesces edits of one group within the window", () => {
    let h = createHistory("");
    h = push(h, "a", { group: "title", now: 1000 });
    h = push(h, "ab", { group: "title", now: 1500 });
    h = push(h, "abc", { group: "title", now: 5000 });
    expect(h.past).toEqual(["", "ab"]);
    expect(undo(h).present).toBe("ab");
  });
});

describe("auto layout", () => {
  it("lays out left to right with successors in later layers and s above f above c", async () => {
    const orders: Orders = {
      id: "x",
      start: "G1",
      goals: [
        { id: "G1", next: { succeed: "G2", fail: "G3", violate: "G4" } },
        { id: "G2", next: { succeed: "COMPLETE" } },
        { id: "G3", next: { succeed: "COMPLETE" } },
        { id: "G4", next: { succeed: "ABORT" } },
      ],
    };
    const layout = await autoLayout(orders);
    const at = (id: string) => layout[id] ?? { x: NaN, y: NaN };
    expect(at("G2").x).toBeGreaterThan(at("G1").x);
    expect(at("COMPLETE").x).toBeGreaterThan(at("G2").x);
    expect(at("G2").y).toBeLessThan(at("G3").y);
    expect(at("G3").y).toBeLessThan(at("G4").y);
  });
});

describe("layered layout", () => {
  it("puts successors in later columns, s above f above c, terminals last, in linear time", () => {
    const orders: Orders = {
      id: "x",
      start: "G1",
      goals: [
        { id: "G1", next: { succeed: "G2", fail: "G3", violate: "G4" } },
        { id: "G2", next: { succeed: "G1", fail: "COMPLETE" } },
        { id: "G3", next: { succeed: "COMPLETE" } },
        { id: "G4", next: { succeed: "ABORT" } },
        { id: "G9", next: {} },
      ],
    };
    const layout = layeredLayout(orders);
    const at = (id: string) => layout[id] ?? { x: NaN, y: NaN };
    expect(at("G2").x).toBeGreaterThan(at("G1").x);
    expect(at("G2").y).toBeLessThan(at("G3").y);
    expect(at("G3").y).toBeLessThan(at("G4").y);
    expect(at("COMPLETE").x).toBeGreaterThan(at("G4").x);
    expect(Object.keys(layout).sort()).toEqual(["ABORT", "COMPLETE", "G1", "G2", "G3", "G4", "G9"]);
    const big: Orders = {
      id: "big",
      start: "G1",
      goals: Array.from({ length: 2000 }, (_, i) => ({
        id: `G${i + 1}`,
        next: { succeed: i < 1999 ? `G${i + 2}` : "COMPLETE", fail: "ABORT", violate: "ABORT" },
      })),
    };
    const t = performance.now();
    const wide = layeredLayout(big);
    expect(performance.now() - t).toBeLessThan(500);
    expect(wide["G2000"]?.x).toBeGreaterThan(wide["G1"]?.x ?? 0);
  });
});

describe("layered layout wraps long chains", () => {
  // Shaped like PiratesSeizingMerchantDefense: a long chain, fail edges back to an early goal,
  // every violate edge into one sink goal that branches to three terminals.
  const n = 48;
  const chain: Orders = {
    id: "pirates-like",
    start: "G1",
    goals: [
      ...Array.from({ length: n }, (_, i) => ({
        id: `G${i + 1}`,
        next: { succeed: i + 1 < n ? `G${i + 2}` : "SINK", fail: i % 5 === 4 ? "G4" : i + 1 < n ? `G${i + 2}` : "SINK", violate: "SINK" },
      })),
      { id: "SINK", next: { succeed: "COMPLETE", fail: "ABORT", violate: "ABORT" } },
    ],
  };
  it.each([1.6, 2.2])("to about the aspect ratio %s, with no two nodes overlapping", (aspect) => {
    const layout = layeredLayout(chain, aspect);
    const boxes = Object.entries(layout).map(([id, p]) => ({ id, ...p, ...(id === "COMPLETE" || id === "ABORT" ? TERMINAL_SIZE : GOAL_SIZE) }));
    const width = Math.max(...boxes.map((b) => b.x + b.width)) - Math.min(...boxes.map((b) => b.x));
    const height = Math.max(...boxes.map((b) => b.y + b.height)) - Math.min(...boxes.map((b) => b.y));
    expect(width / height).toBeGreaterThan(aspect / 2);
    expect(width / height).toBeLessThan(aspect * 2);
    // Fits a 700 x 420 px canvas at a zoom of 0.15 or more (the editor's least zoom).
    expect(Math.min(700 / width, 420 / height)).toBeGreaterThan(0.15);
    for (let i = 0; i < boxes.length; i++) {
      for (let j = i + 1; j < boxes.length; j++) {
        const a = boxes[i]!, b = boxes[j]!;
        const overlap = a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
        expect(overlap, `${a.id} / ${b.id}`).toBe(false);
      }
    }
  });
});
