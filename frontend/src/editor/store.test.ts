import { describe, expect, it } from "vitest";

import type { MissionDetail, Report } from "../api/client";
import type { Orders } from "./graph";
import type { Refusal } from "./refusal";
import { createEditorStore } from "./store";

const orders = {
  format: "countersign.orders/1",
  id: "m1",
  start: "G1",
  goals: [{ id: "G1", next: { succeed: "T1", fail: "T1", violate: "T1" } }],
  terminals: [{ id: "T1", kind: "complete" }],
} as unknown as Orders;

function opened() {
  const mission = {
    id: "m1",
    revision: 3,
    orders,
    layout: { G1: { x: 0, y: 0 }, T1: { x: 200, y: 0 } },
  } as unknown as MissionDetail;
  return createEditorStore(mission);
}

describe("the editor's store", () => {
  it("has named actions only: no generic patch of its state", () => {
    const state = opened().getState() as unknown as Record<string, unknown>;
    expect("set" in state).toBe(false);
    expect(typeof state.saveRefused).toBe("function");
  });

  it("a refused save shows the refusal on the panel that holds its field", () => {
    const store = opened();
    const refusal = { panel: "editor-areas" } as unknown as Refusal;
    store.getState().saveRefused(new Error("no"), refusal);
    expect(store.getState()).toMatchObject({ saveState: "error", refusal, panel: "editor-areas" });
    store.getState().saveRefused(new Error("again"), null);
    expect(store.getState()).toMatchObject({ saveState: "error", refusal: null, panel: "editor-areas" });
  });

  it("opening another scope drops the highlight and focus; replacing the scope keeps them", () => {
    const store = opened();
    const highlight = { path: { goals: ["G1"], outcomes: ["succeed"], terminal: "T1" }, label: "path 1" };
    store.getState().showHighlight(highlight);
    store.getState().focusGoal("G1");
    store.getState().replaceScope({ member: null, path: [] });
    expect(store.getState()).toMatchObject({ highlight, focus: "G1" });
    store.getState().openScope({ member: null, path: ["G1"] });
    expect(store.getState()).toMatchObject({ highlight: null, focus: null, scope: { member: null, path: ["G1"] } });
  });

  it("a save moves the revision and base; their reload takes their whole state", () => {
    const store = opened();
    const next = { ...orders, title: "mine" } as Orders;
    store.getState().ordersSaved(4, next);
    expect(store.getState()).toMatchObject({ revision: 4, savedRevision: 4, base: next, saveError: null });
    store.getState().saveFinished(false);
    expect(store.getState().saveState).toBe("pending");
    const theirs = { ...opened().getState(), revision: 7, orders: next, layout: {} } as unknown as MissionDetail;
    store.getState().theirsReloaded(theirs);
    expect(store.getState()).toMatchObject({ revision: 7, savedRevision: 7, lastChecked: next, saveState: "saved", conflict: null });
  });

  it("a check's report is kept with the orders it is of, and its time only when measured", () => {
    const store = opened();
    const report = { ok: true, findings: [] } as unknown as Report;
    store.getState().checked(orders, report, null);
    expect(store.getState()).toMatchObject({ report, lastChecked: orders, checkMs: null });
    store.getState().checked(orders, report, 120);
    expect(store.getState().checkMs).toBe(120);
  });
});
