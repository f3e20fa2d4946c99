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
      { what: "Expected energy", value: "593.8 Wh (p50 600 Wh)" },
    ]);
  });

  it("prints costs with their units, never a raw float", () => {
    const rows = probabilityRows({
      exact: true,
      terminals: {},
      violation: { min: 0, max: 0 },
      expected: {
        energy_wh: { min: 339.0160693893765, max: 339.0160693893765, quantiles: { "0.5": 339.0160693893765, "0.9": 1200.25 }, unknown_cost: [] },
        duration_s: { min: 3725.4, max: 3725.4, quantiles: { "0.5": 95.2 }, unknown_cost: [] },
      },
      unknown: [],
      intervals: [],
    });
    expect(rows.slice(1)).toEqual([
      { what: "Expected energy", value: "339 Wh (p50 339 Wh, p90 1,200.3 Wh)" },
      { what: "Expected time", value: "1 h 02 min (p50 1 min 35 s)" },
    ]);
  });

  it("reads a path's probability or its bounds, and nothing else", () => {
    expect(pathProbability(0.0227259648)).toBe("0.02273");
    expect(pathProbability([0.1, 0.2])).toBe("0.1 to 0.2");
    expect(pathProbability("<b>")).toBeNull();
    expect(pathProbability(undefined)).toBeNull();
  });
});
