import { describe, expect, it } from "vitest";

import type { Finding } from "../api/client";
import type { Orders } from "./graph";
import { addRefinement, crumbsOf, findingsAt, layoutAt, localFindings, ordersAt, prefixOf, withLayoutAt, withOrdersAt } from "./scope";
import { applyScoped } from "./useScopedDraft";

const refined = {
  id: "m",
  start: "G1",
  goals: [
    {
      id: "G1",
      title: "Search",
      next: { succeed: "C", fail: "C", violate: "C" },
      refines: { start: "G1.1", goals: [{ id: "G1.1", next: { succeed: "T" } }], terminals: [{ id: "T", kind: "complete", returns: "succeed" }] },
    },
  ],
  terminals: [{ id: "C", kind: "complete" }],
} as unknown as Orders;

const team = {
  id: "t",
  team: [
    { vehicle: "a", orders: { id: "a", start: "G1", goals: [{ id: "G1", meet: "R1" }] } },
    { vehicle: "b", orders: { id: "b", start: "G1", goals: [{ id: "G1", meet: "R1" }] } },
  ],
} as unknown as Orders;

describe("scope", () => {
  it("reads and writes a refinement and a team member's orders", () => {
    const inside = ordersAt(refined, { member: null, path: ["G1"] })!;
    expect(inside.goals?.map((g) => g.id)).toEqual(["G1.1"]);
    const changed = withOrdersAt(refined, { member: null, path: ["G1"] }, { ...inside, goals: [...inside.goals!, { id: "G1.2" }] } as Orders);
    expect(changed.goals?.[0]?.refines?.goals?.map((g) => g.id)).toEqual(["G1.1", "G1.2"]);
    expect(changed.terminals).toEqual(refined.terminals);
    const b = withOrdersAt(team, { member: 1, path: [] }, { id: "b", goals: [{ id: "G9" }] } as unknown as Orders);
    expect((b.team?.[1]?.orders as unknown as Orders).goals?.map((g) => g.id)).toEqual(["G9"]);
    expect(b.team?.[0]).toBe(team.team?.[0]);
    expect(ordersAt(refined, { member: null, path: ["G9"] })).toBeNull();
  });

  it("keeps positions under full ids and findings as the canvas names them", () => {
    expect(prefixOf(team, { member: 1, path: ["G1"] })).toBe("b/G1/");
    const layout = { G1: { x: 1, y: 1 }, "G1/G1.1": { x: 2, y: 2 }, "G1/G1.1/X": { x: 3, y: 3 } };
    const inside = ordersAt(refined, { member: null, path: ["G1"] })!;
    expect(layoutAt(layout, "G1/", inside)["G1.1"]).toEqual({ x: 2, y: 2 });
    expect(withLayoutAt(layout, "G1/", { "G1.1": { x: 5, y: 5 } })).toEqual({ G1: { x: 1, y: 1 }, "G1/G1.1": { x: 5, y: 5 }, "G1/G1.1/X": { x: 3, y: 3 } });
    const findings = [
      { code: "REFINE", severity: "error", subjects: ["G1/T"], message: "" },
      { code: "SINK", severity: "error", subjects: ["G2"], message: "" },
      { code: "TEAM", severity: "error", subjects: ["R1", "a/G1"], message: "" },
    ] as Finding[];
    expect(findingsAt(findings, "G1/", false).map((f) => f.code)).toEqual(["REFINE"]);
    expect(findingsAt(findings, "b/", true).map((f) => f.code)).toEqual(["TEAM"]);
    expect(localFindings(findings, "").find((f) => f.code === "REFINE")?.subjects).toEqual(["G1"]);
    expect(localFindings(findings, "a/").map((f) => f.subjects)).toEqual([["G1"]]);
  });

  it("adds a refinement whose terminals return the parent's outcomes, edited through the scope", () => {
    const orders = addRefinement({ ...refined, goals: [{ id: "G2", title: "Sample" }] } as Orders, "G2");
    const refines = orders.goals?.[0]?.refines;
    expect(refines?.start).toBe("G2.1");
    expect(refines?.terminals?.map((t) => t.returns)).toEqual(["succeed", "fail", "violate"]);
    const scope = { member: null, path: ["G2"] };
    const next = applyScoped({ orders, layout: {} }, scope, (d) => ({ ...d, orders: { ...d.orders, start: "DONE" } }));
    expect(next.orders.goals?.[0]?.refines?.start).toBe("DONE");
    expect(crumbsOf(orders, scope).map((c) => c.label)).toEqual(["Mission", "G2 Sample"]);
  });
});
