import { describe, expect, it } from "vitest";
import { pathProbability, probabilityRows } from "./probabilities";

describe("outcome probabilities", () => {
  it("shows exact figures once and bounds as a range", () => {
    const rows = probabilityRows({
      exact: false,
      terminals: { COMPLETE: { min: 0.61, max: 0.61 }, ABORT: { min: 0.2, max: 0.39 } },
      violation: { min: 0.1, max: 0.3 },
      expected: { energy_wh: { min: 593.79, max: 593.79, quantiles: { "0.5": 600 }, unknown_cost: [] } },
      unknown: [],
      intervals: ["G2"],
    });
    expect(rows).toEqual([
      { what: "Ends at COMPLETE", value: "0.61" },
      { what: "Ends at ABORT", value: "0.2 to 0.39" },
      { what: "Any constraint violated", value: "0.1 to 0.3" },
      { what: "Expected energy (Wh)", value: "593.79 (p50 600)" },
    ]);
  });

  it("reads a path's probability or its bounds, and nothing else", () => {
    expect(pathProbability(0.0227259648)).toBe("0.02273");
    expect(pathProbability([0.1, 0.2])).toBe("0.1 to 0.2");
    expect(pathProbability("<b>")).toBeNull();
    expect(pathProbability(undefined)).toBeNull();
  });
});
