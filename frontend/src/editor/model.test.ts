import { describe, expect, it } from "vitest";

import { applyCompletion, checkExpr, completions, knownQuantities, parseExpr, tokenize } from "./expr";
import { checkConnection, edgeMarkers, findingPath, type Orders, pathElements } from "./graph";
import {
  addArea,
  addFeature,
  addQuantity,
  addVertex,
  copyGoals,
  paramsToText,
  parseParams,
  pasteGoals,
  patch,
  readClip,
  renameArea,
  renameFeature,
  setNormKind,
  addNorm,
  updateFeature,
  updateNorm,
  updateQuantity,
} from "./model";
import { fitView, fromMetres, project, unproject } from "./planview";

const base: Orders = {
  format: "countersign.orders/1",
  id: "m",
  start: "G1",
  goals: [
    { id: "G1", title: "One", area: "A", next: { succeed: "G2", fail: "ABORT", violate: "ABORT" } },
    { id: "G2", title: "Two", next: { succeed: "COMPLETE", fail: "G1" } },
  ],
  constraints: [{ id: "C1", text: "", applies_to: "mission" }],
  areas: [{ id: "A", polygon: [[36.7, -121.9], [36.7, -121.87], [36.695, -121.87]] }],
};

describe("expression tokenizer and parser", () => {
  it("tokenizes numbers, names, strings and two-character operators with columns", () => {
    const { tokens, error } = tokenize("depth_m >= 20.5 and behavior != 'sample'");
    expect(error).toBeUndefined();
    expect(tokens.map((t) => t.text)).toEqual(["depth_m", ">=", "20.5", "and", "behavior", "!=", "sample", ""]);
    expect(tokens[1]!.col).toBe(9);
  });
  it("reads the exemplar's expressions and the names they use", () => {
    expect(parseExpr("lane_distance_m >= 1000 or depth_m >= 20")).toEqual({ names: ["lane_distance_m", "depth_m"] });
    expect(parseExpr("not (behavior == 'sample' and context('marine_protected_area'))").error).toBeUndefined();
    expect(parseExpr("3 <= altitude_m <= 12 implies -speed_mps * 2 / 3 + 1 > 0").error).toBeUndefined();
  });
  it("reports the column of a syntax error", () => {
    expect(parseExpr("depth_m >=")).toEqual({ names: ["depth_m"], error: { message: "expected a value after '>='", col: 11 } });
    expect(parseExpr("(depth_m > 1").error?.message).toMatch(/expected '\)'/);
    expect(parseExpr("depth_m = 3").error).toEqual({ message: "'=' alone is not an operator; write '==' or '!='", col: 9 });
    expect(parseExpr("a b").error?.col).toBe(3);
    expect(parseExpr("'open").error?.message).toBe("unterminated string");
    expect(parseExpr("context(x)").error?.message).toMatch(/quoted tag/);
  });
  it("flags unknown quantities against the orders' table", () => {
    const known = knownQuantities({ quantities: { reef_m: {} }, goals: [{ id: "G1", envelope: { depth_x: [0, 1] } }] });
    expect(known).toContain("reef_m");
    expect(known).toContain("depth_x");
    expect(known).toContain("depth_m");
    expect(checkExpr("reef_m > 2", known)).toBeNull();
    expect(checkExpr("x >= 2 or reeef_m > 1", known)).toEqual({ message: "unknown quantity 'x'", col: 1 });
  });
});

describe("expression completion", () => {
  const known = ["depth_m", "lane_distance_m", "nav_error_m"];
  it("offers quantities that start with the word at the caret", () => {
    expect(completions("lane_d", 6, known)).toEqual({ start: 0, items: ["lane_distance_m"] });
    expect(completions("x > 1 and d", 11, known).items).toEqual(["depth_m"]);
    expect(completions("depth_m", 7, known).items).toEqual([]);
    expect(completions("x > 1 ", 6, known).items).toEqual([]);
    expect(completions("context('d", 10, known).items).toEqual([]);
  });
  it("replaces the whole word and puts the caret after it", () => {
    expect(applyCompletion("lane_d >= 3", 4, "lane_distance_m")).toEqual({ text: "lane_distance_m >= 3", caret: 15 });
    expect(applyCompletion("co", 2, "context")).toEqual({ text: "context('", caret: 9 });
  });
});

describe("copy and paste of goals", () => {
  const layout = { G1: { x: 0, y: 0 }, G2: { x: 300, y: 0 } };
  it("renames clashing ids, keeps internal edges and edges to known nodes", () => {
    const clip = copyGoals(base, layout, ["G1", "G2"])!;
    const text = JSON.stringify(clip);
    const result = pasteGoals(base, layout, readClip(text)!);
    expect(result.ids).toEqual(["G3", "G4"]);
    const pasted = result.orders.goals!.slice(2);
    expect(pasted[0]!.next).toEqual({ succeed: "G4", fail: "ABORT", violate: "ABORT" });
    expect(pasted[1]!.next).toEqual({ succeed: "COMPLETE", fail: "G3" });
    expect(result.layout.G3).toEqual({ x: 40, y: 40 });
    expect(result.orders.start).toBe("G1");
  });
  it("pastes into another mission: free ids kept, unknown targets dropped", () => {
    const other: Orders = { id: "other", goals: [{ id: "G9", next: {} }], start: "G9", terminals: [{ id: "END", kind: "complete" }] };
    const clip = copyGoals(base, layout, ["G1"])!;
    const result = pasteGoals(other, {}, clip);
    expect(result.ids).toEqual(["G1"]);
    expect(result.orders.goals![1]!.next).toEqual({});
  });
  it("does not rename onto a constraint id", () => {
    const orders: Orders = { id: "m", goals: [{ id: "C1" }], constraints: [{ id: "G1" }] };
    const clip = copyGoals(orders, {}, ["C1"])!;
    expect(pasteGoals(orders, {}, clip).ids).toEqual(["G2"]);
  });
  it("ignores clipboard text that is not goals", () => {
    expect(readClip("hello")).toBeNull();
    expect(readClip('{"format": "other"}')).toBeNull();
    expect(copyGoals(base, layout, ["COMPLETE"])).toBeNull();
  });
});

describe("connections", () => {
  it("allows one successor per outcome and only to known nodes", () => {
    expect(checkConnection(base, "G2", "violate", "ABORT").ok).toBe(true);
    expect(checkConnection(base, "G2", "succeed", "ABORT").ok).toBe(false);
    expect(checkConnection(base, "G2", "violate", "NOPE").ok).toBe(false);
    expect(checkConnection(base, "COMPLETE", "succeed", "G1").ok).toBe(false);
    expect(checkConnection(base, "G2", "in", "G1").ok).toBe(false);
  });
});

describe("finding markers on edges and counterexample paths", () => {
  const edges = [
    { id: "G1:succeed:G2", source: "G1", target: "G2" },
    { id: "G2:fail:G1", source: "G2", target: "G1" },
    { id: "G1:fail:ABORT", source: "G1", target: "ABORT" },
  ];
  it("marks the edges of a loop", () => {
    const marks = edgeMarkers([{ code: "G7", severity: "error", subjects: ["G1", "G2"] }], edges);
    expect([...marks.keys()].sort()).toEqual(["G1:succeed:G2", "G2:fail:G1"]);
  });
  it("reads BUDGET and PROPERTY paths and marks their edges", () => {
    const budget = { code: "BUDGET", severity: "error", subjects: ["G1", "G2", "COMPLETE"], goals: ["G1", "G2"], outcomes: ["succeed", "succeed"], terminal: "COMPLETE" };
    const property = { code: "PROPERTY", severity: "error", subjects: [], path: { goals: ["G1"], outcomes: ["fail"], terminal: "ABORT" } };
    expect(findingPath(budget)).toEqual({ goals: ["G1", "G2"], outcomes: ["succeed", "succeed"], terminal: "COMPLETE" });
    const path = findingPath(property)!;
    expect([...pathElements(path).edges]).toEqual(["G1:fail:ABORT"]);
    expect(findingPath({ code: "G10", subjects: ["G3"] })).toBeNull();
    const marks = edgeMarkers([budget], edges);
    expect(marks.get("G1:succeed:G2")?.codes).toEqual(["BUDGET"]);
  });
});

describe("orders edits beside the graph", () => {
  it("never writes empty fields (the digest covers what the author wrote)", () => {
    expect(patch({ a: 1, b: "x" }, { a: undefined, b: "", c: [], d: {}, e: 0 })).toEqual({ e: 0 });
  });
  it("renames an area and the goals that use it, refusing clashes", () => {
    const { orders } = addArea(base);
    expect(renameArea(orders, "AREA1", "A").error).toMatch(/exists/);
    const renamed = renameArea(base, "A", "B").orders;
    expect(renamed.goals![0]!.area).toBe("B");
    expect(addVertex(renamed, "B").areas).toBeDefined();
  });
  it("keeps feature lists even when empty", () => {
    let orders: Orders = { id: "m", vehicle: "v", vehicles: [{ id: "v" }] };
    orders = addFeature(orders, "v").orders;
    orders = renameFeature(orders, "v", "feature-1", "sampler").orders;
    orders = updateFeature(orders, "v", "sampler", { title: "Water sampler", measures: [] });
    expect((orders.vehicles as { features: unknown[] }[])[0]!.features).toEqual([
      { id: "sampler", title: "Water sampler", fulfills: [], measures: [] },
    ]);
  });
  it("edits quantities and norms", () => {
    let orders = addQuantity(base, "depth_m").orders;
    expect(addQuantity(orders, "depth_m").error).toMatch(/exists/);
    expect(addQuantity(orders, "9x").error).toBeDefined();
    orders = updateQuantity(orders, "depth_m", { unit: "m", min: 0, max: undefined });
    expect(orders.quantities).toEqual({ depth_m: { unit: "m", min: 0 } });
    orders = addNorm(orders).orders;
    expect(orders.norms).toEqual([{ id: "N1", context: "marine_protected_area", permitted: "true" }]);
    orders = setNormKind(orders, "N1", "forbidden");
    orders = updateNorm(orders, "N1", { forbidden: "behavior == 'sample'" });
    orders = setNormKind(orders, "N1", "obligated");
    expect(orders.norms).toEqual([{ id: "N1", context: "marine_protected_area", obligated: "behavior == 'sample'" }]);
  });
  it("reads goal parameters as numbers, booleans or text", () => {
    expect(parseParams("pd 0.8\npartner vehicle-2\nloud true")).toEqual({ params: { pd: 0.8, partner: "vehicle-2", loud: true } });
    expect(parseParams("oops").error).toMatch(/Line 1/);
    expect(paramsToText({ pd: 0.8, partner: "vehicle-2" })).toBe("pd 0.8\npartner vehicle-2");
  });
});

describe("plan-view geometry", () => {
  it("projects north up and inverts the projection", () => {
    const pts: [number, number][] = [[36.7, -121.9], [36.8, -121.8]];
    const view = fitView(pts, 500, 300, 20);
    const [x1, y1] = project(view, pts[0]!);
    const [x2, y2] = project(view, pts[1]!);
    expect(x2).toBeGreaterThan(x1);
    expect(y2).toBeLessThan(y1); // north is up
    const back = unproject(view, x1, y1);
    expect(back[0]).toBeCloseTo(36.7, 5);
    expect(back[1]).toBeCloseTo(-121.9, 5);
    for (const [x, y] of [[x1, y1], [x2, y2]]) {
      expect(x).toBeGreaterThanOrEqual(20 - 1e-6);
      expect(x).toBeLessThanOrEqual(480 + 1e-6);
      expect(y).toBeGreaterThanOrEqual(20 - 1e-6);
      expect(y).toBeLessThanOrEqual(280 + 1e-6);
    }
  });
  it("fits a single point and converts local metres back to degrees", () => {
    const view = fitView([[10, 10]], 100, 100);
    expect(Number.isFinite(view.scale)).toBe(true);
    const [lat, lon] = fromMetres([36.8, -121.8], [0, 1111.95]);
    expect(lat).toBeCloseTo(36.81, 4);
    expect(lon).toBeCloseTo(-121.8, 6);
  });
});
