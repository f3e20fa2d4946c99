import fc from "fast-check";
import { describe, expect, it } from "vitest";

import { type GoalSpec, type Orders, stable } from "./graph";
import { mergeOrders, resolveMerge } from "./merge";

function chain(n: number): Orders {
  const goals: GoalSpec[] = Array.from({ length: n }, (_, i) => ({
    id: `G${i + 1}`,
    title: `Goal ${i + 1}`,
    next: { succeed: i + 1 < n ? `G${i + 2}` : "COMPLETE", fail: "ABORT" },
  }));
  return { format: "countersign.orders/1", id: "m", title: "Base", start: "G1", goals, constraints: [{ id: "C1", text: "Stay", applies_to: "mission" }] };
}
function editGoal(o: Orders, id: string, patch: Partial<GoalSpec>): Orders {
  return { ...o, goals: (o.goals ?? []).map((g) => (g.id === id ? { ...g, ...patch } : g)) };
}
const goal = (o: Orders, id: string) => (o.goals ?? []).find((g) => g.id === id);

describe("three-way merge of the orders", () => {
  it("merges edits of different goals without a conflict and says what merged", () => {
    const base = chain(4);
    const mine = editGoal(base, "G2", { title: "Mine" });
    const theirs = editGoal(base, "G3", { behavior: "survey" });
    const result = mergeOrders(base, mine, theirs);
    expect(result.conflicts).toEqual([]);
    expect(goal(result.orders, "G2")?.title).toBe("Mine");
    expect(goal(result.orders, "G3")?.behavior).toBe("survey");
    expect(result.merged).toEqual(["Goal G2: your change kept.", "Goal G3: their change kept."]);
  });

  it("merges different fields of one goal, and different outcomes of its next", () => {
    const base = chain(3);
    const mine = editGoal(base, "G2", { title: "Mine", next: { succeed: "G3", fail: "G1" } });
    const theirs = editGoal(base, "G2", { behavior: "loiter", next: { succeed: "G3", fail: "ABORT", violate: "ABORT" } });
    const result = mergeOrders(base, mine, theirs);
    expect(result.conflicts).toEqual([]);
    expect(goal(result.orders, "G2")).toEqual({ id: "G2", title: "Mine", behavior: "loiter", next: { succeed: "G3", fail: "G1", violate: "ABORT" } });
    expect(result.merged).toEqual(["Goal G2: your change and theirs merged."]);
  });

  it("keeps additions of both sides, theirs' order first", () => {
    const base = chain(2);
    const mine = { ...base, goals: [...(base.goals ?? []), { id: "G9", title: "Mine" }] };
    const theirs = { ...base, goals: [...(base.goals ?? []), { id: "G8", title: "Theirs" }], title: "Renamed" };
    const result = mergeOrders(base, mine, theirs);
    expect(result.conflicts).toEqual([]);
    expect((result.orders.goals ?? []).map((g) => g.id)).toEqual(["G1", "G2", "G8", "G9"]);
    expect(result.orders.title).toBe("Renamed");
  });

  it("reports the same field changed differently as one conflict, resolved per item", () => {
    const base = chain(3);
    const mine = editGoal(editGoal(base, "G2", { title: "Mine" }), "G1", { title: "Only mine" });
    const theirs = editGoal(base, "G2", { title: "Theirs", behavior: "x" });
    const result = mergeOrders(base, mine, theirs);
    expect(result.conflicts.map((c) => [c.key, c.fields])).toEqual([["goals:G2", ["title"]]]);
    const conflict = result.conflicts[0]!;
    expect((conflict.mine as GoalSpec).title).toBe("Mine");
    expect((conflict.theirs as GoalSpec).title).toBe("Theirs");
    expect(goal(resolveMerge(result, { "goals:G2": "mine" }), "G2")?.title).toBe("Mine");
    expect(goal(resolveMerge(result, { "goals:G2": "theirs" }), "G2")).toEqual(goal(theirs, "G2"));
    expect(goal(resolveMerge(result, {}), "G1")?.title).toBe("Only mine");
  });

  it("treats a deletion against a change as a conflict (nothing lost silently)", () => {
    const base = chain(3);
    const mine = { ...base, goals: (base.goals ?? []).filter((g) => g.id !== "G3") };
    const theirs = editGoal(base, "G3", { title: "Kept?" });
    const result = mergeOrders(base, mine, theirs);
    expect(result.conflicts.map((c) => c.key)).toEqual(["goals:G3"]);
    expect(goal(resolveMerge(result, { "goals:G3": "mine" }), "G3")).toBeUndefined();
    expect(goal(resolveMerge(result, { "goals:G3": "theirs" }), "G3")?.title).toBe("Kept?");
  });

  it("merges terminals added by one side when the others use the defaults", () => {
    const base = chain(1);
    const mine = { ...base, terminals: [{ id: "COMPLETE", kind: "complete" as const, title: "Mission complete" }, { id: "ABORT", kind: "abort" as const, title: "Mission abort" }, { id: "ABORT2", kind: "abort" as const }] };
    const theirs = { ...base, title: "T" };
    const result = mergeOrders(base, mine, theirs);
    expect(result.conflicts).toEqual([]);
    expect((result.orders.terminals ?? []).map((t) => t.id)).toEqual(["COMPLETE", "ABORT", "ABORT2"]);
  });

  // ---- Properties over random edits ----
  const ids = Array.from({ length: 6 }, (_, i) => `G${i + 1}`);
  const goalEdit = fc.record({
    id: fc.constantFrom(...ids),
    title: fc.option(fc.string({ maxLength: 5 }), { nil: undefined }),
    behavior: fc.option(fc.constantFrom("a", "b", "c"), { nil: undefined }),
    succeed: fc.option(fc.constantFrom(...ids, "COMPLETE"), { nil: undefined }),
  });
  const apply = (o: Orders, edits: { id: string; title?: string; behavior?: string; succeed?: string }[]) =>
    edits.reduce((acc, e) => {
      const g = goal(acc, e.id)!;
      return editGoal(acc, e.id, {
        ...(e.title !== undefined ? { title: e.title } : {}),
        ...(e.behavior !== undefined ? { behavior: e.behavior } : {}),
        ...(e.succeed !== undefined ? { next: { ...g.next, succeed: e.succeed } } : {}),
      });
    }, o);
  const edits = fc.array(goalEdit, { maxLength: 6 });

  it("is the identity when one side made no change, and when both made the same", () => {
    fc.assert(
      fc.property(edits, (e) => {
        const base = chain(6);
        const changed = apply(base, e);
        for (const result of [mergeOrders(base, changed, base), mergeOrders(base, base, changed), mergeOrders(base, changed, changed)]) {
          expect(result.conflicts).toEqual([]);
          expect(stable(result.orders)).toBe(stable(changed));
        }
      }),
    );
  });

  it("keeps every edit of both sides when they touch different goals", () => {
    fc.assert(
      fc.property(edits, edits, (a, b) => {
        const base = chain(6);
        const mineIds = new Set(a.map((x) => x.id));
        const theirsEdits = b.filter((x) => !mineIds.has(x.id));
        const mine = apply(base, a);
        const theirs = apply(base, theirsEdits);
        const result = mergeOrders(base, mine, theirs);
        expect(result.conflicts).toEqual([]);
        for (const id of ids) {
          const expected = mineIds.has(id) ? goal(mine, id) : goal(theirs, id);
          expect(stable(goal(result.orders, id))).toBe(stable(expected));
        }
      }),
    );
  });

  it("finds the same conflicts whichever side is mine, and loses neither side's version", () => {
    fc.assert(
      fc.property(edits, edits, (a, b) => {
        const base = chain(6);
        const mine = apply(base, a);
        const theirs = apply(base, b);
        const one = mergeOrders(base, mine, theirs);
        const other = mergeOrders(base, theirs, mine);
        expect(one.conflicts.map((c) => c.key).sort()).toEqual(other.conflicts.map((c) => c.key).sort());
        const allMine = Object.fromEntries(one.conflicts.map((c) => [c.key, "mine" as const]));
        const allTheirs = Object.fromEntries(one.conflicts.map((c) => [c.key, "theirs" as const]));
        for (const c of one.conflicts) {
          const id = c.key.split(":")[1]!;
          expect(stable(goal(resolveMerge(one, allMine), id))).toBe(stable(goal(mine, id)));
          expect(stable(goal(resolveMerge(one, allTheirs), id))).toBe(stable(goal(theirs, id)));
        }
      }),
    );
  });
});
