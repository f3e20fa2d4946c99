import { describe, expect, it } from "vitest";

import { profileDiff, showValue } from "./profileDiff";

describe("profileDiff", () => {
  it("names each changed field and ignores empty defaults", () => {
    const before = { id: "auv", behaviors: ["transit"], features: [], title: "AUV" };
    const after = { id: "auv", behaviors: ["transit", "recover"], title: "AUV" };
    expect(profileDiff(before, after)).toEqual([
      { field: "behaviors", before: ["transit"], after: ["transit", "recover"] },
    ]);
    expect(profileDiff(before, { ...before })).toEqual([]);
    // A field written on one side only is a change (a new speed, a dropped budget).
    expect(profileDiff(before, { ...before, speed_mps: 1.5 })).toEqual([
      { field: "speed_mps", before: undefined, after: 1.5 },
    ]);
  });

  it("names the nested field that changed, not the whole object", () => {
    const before = {
      id: "auv",
      envelope: { depth_m: [0, 100], speed_mps: [0, 2] },
      budget: { energy_wh: 1500 },
      features: [
        { id: "nav", fulfills: ["transit"], measures: ["depth_m"] },
        { id: "cam", fulfills: ["area_search"], measures: [] },
      ],
    };
    const after = {
      id: "auv",
      envelope: { depth_m: [0, 60], speed_mps: [0, 2] },
      budget: { energy_wh: 1500, duration_s: 7200 },
      features: [
        { id: "nav", fulfills: ["transit"], measures: ["depth_m", "nav_error_m"] },
        { id: "sonar", fulfills: ["area_search"] },
      ],
    };
    expect(profileDiff(before, after)).toEqual([
      { field: "envelope.depth_m", before: [0, 100], after: [0, 60] },
      { field: "budget.duration_s", before: undefined, after: 7200 },
      { field: "features[nav].measures", before: ["depth_m"], after: ["depth_m", "nav_error_m"] },
      { field: "features[cam]", before: before.features[1], after: undefined },
      { field: "features[sonar]", before: undefined, after: after.features[1] },
    ]);
  });

  it("shows lists of words joined", () => {
    expect(showValue(["a", "b"])).toBe("a, b");
    expect(showValue(undefined)).toBe("(none)");
    expect(showValue({ depth_m: [0, 5] })).toBe('{"depth_m":[0,5]}');
  });
});
