import { describe, expect, it } from "vitest";

import { ApiError } from "../api/client";
import type { Orders } from "./graph";
import { addNorm } from "./model";
import { fieldOf, refusalOf } from "./refusal";

const orders = {
  format: "countersign.orders/1",
  id: "m",
  goals: [{ id: "G1", title: "One", next: {} }],
  norms: [{ id: "N1", context: "harbour", forbidden: "behavior == 'sample'" }, { id: "N2", context: "x", permitted: "true" }],
  constraints: [{ id: "C1", expr: "depth_m <= 10" }],
} as unknown as Orders;

describe("a refused save names its field", () => {
  it("maps a norm's context, expression and modality to its inputs on the Norms tab", () => {
    expect(fieldOf(orders, "$.norms[1].context")).toEqual({ fieldId: "norm-N2-context", panel: "editor-norms", select: null });
    expect(fieldOf(orders, "$.norms[0].forbidden")).toMatchObject({ fieldId: "norm-N1-expr" });
    expect(fieldOf(orders, "$.norms[0]")).toMatchObject({ fieldId: "norm-N1-expr" });
    expect(fieldOf(orders, "$.constraints[0].expr")).toMatchObject({ fieldId: "c-C1-expr", panel: "editor-constraints" });
    expect(fieldOf(orders, "$.goals[0].title")).toEqual({ fieldId: "goal-title", panel: null, select: "G1" });
    expect(fieldOf(orders, "$.title")).toEqual({ fieldId: null, panel: null, select: null });
  });

  it("reads the first error of a 422 problem document", () => {
    const error = new ApiError(422, { title: "Invalid orders", errors: [{ path: "$.norms[1].context", message: "Field required" }] });
    expect(refusalOf(error, orders)).toMatchObject({ message: "$.norms[1].context: Field required", fieldId: "norm-N2-context" });
    expect(refusalOf(new ApiError(412, {}), orders)).toBeNull();
    expect(refusalOf(new Error("offline"), orders)).toBeNull();
  });
});

describe("new items are created valid", () => {
  it("a new norm has a context and exactly one modality with an expression", () => {
    const { orders: next, id } = addNorm(orders);
    const norm = (next.norms as Record<string, unknown>[]).find((n) => n.id === id)!;
    expect(typeof norm.context).toBe("string");
    expect((norm.context as string).length).toBeGreaterThan(0);
    const modalities = ["forbidden", "obligated", "permitted"].filter((k) => typeof norm[k] === "string" && norm[k] !== "");
    expect(modalities).toHaveLength(1);
  });
});
