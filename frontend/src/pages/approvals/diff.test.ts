import { describe, expect, it } from "vitest";

import { describeDiff, diffOrders } from "./diff";

const before = {
  format: "countersign.orders/1",
  id: "m",
  title: "Survey",
  vehicle: "auv1",
  start: "G1",
  goals: [
    { id: "G1", title: "Search Area A", next: { succeed: "G2", fail: "ABORT", violate: "ABORT" } },
    { id: "G2", title: "Sample", next: { succeed: "COMPLETE", fail: "ABORT", violate: "ABORT" } },
  ],
  constraints: [{ id: "C1", text: "Stay above 5 m" }],
  norms: [{ id: "N1", context: "harbor", forbidden: "anchor" }],
};

describe("diffOrders", () => {
  it("finds nothing between equal orders, whatever the key order", () => {
    const reverse = (v: unknown): unknown =>
      Array.isArray(v)
        ? v.map(reverse)
        : v && typeof v === "object"
          ? Object.fromEntries(Object.entries(v).reverse().map(([k, x]) => [k, reverse(x)]))
          : v;
    expect(diffOrders(before, reverse(before) as typeof before).same).toBe(true);
  });

  it("lists goals, constraints and norms added, removed and changed, field by field", () => {
    const after = {
      ...before,
      title: "Survey v2",
      goals: [
        { ...before.goals[0]!, title: "Search Area A, north half" },
        { id: "G3", title: "Return", next: { succeed: "COMPLETE", fail: "ABORT", violate: "ABORT" } },
      ],
      constraints: [{ id: "C1", text: "Stay above 10 m" }, { id: "C2", text: "No night dives" }],
      norms: [],
    };
    const diff = diffOrders(before, after);
    expect(diff.same).toBe(false);
    const goals = diff.sections.find((s) => s.key === "goals")!;
    expect(goals.added.map((a) => a.id)).toEqual(["G3"]);
    expect(goals.removed.map((r) => r.id)).toEqual(["G2"]);
    expect(goals.changed).toEqual([
      { id: "G1", label: "G1 (Search Area A, north half)", fields: [{ field: "title", before: "Search Area A", after: "Search Area A, north half" }] },
    ]);
    expect(describeDiff(diff)).toEqual([
      "title changed: Survey → Survey v2",
      "Goals: added G3 (Return)",
      "Goals: removed G2 (Sample)",
      "Goals: changed G1 (title)",
      "Constraints: added C2 (No night dives)",
      "Constraints: changed C1 (text)",
      "Norms: removed N1",
    ]);
  });

  it("treats missing terminals as the default ones", () => {
    const explicit = {
      ...before,
      terminals: [
        { id: "COMPLETE", kind: "complete", title: "Mission complete" },
        { id: "ABORT", kind: "abort", title: "Mission abort" },
      ],
    };
    expect(diffOrders(before, explicit).same).toBe(true);
  });
});
