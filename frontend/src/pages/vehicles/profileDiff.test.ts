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

  it("shows lists of words joined", () => {
    expect(showValue(["a", "b"])).toBe("a, b");
    expect(showValue(undefined)).toBe("(none)");
    expect(showValue({ depth_m: [0, 5] })).toBe('{"depth_m":[0,5]}');
  });
});
