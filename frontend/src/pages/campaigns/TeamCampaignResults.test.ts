import { describe, expect, it } from "vitest";

import { jointParts } from "./TeamCampaignResults";

describe("jointParts", () => {
  it("splits a joint end into each vehicle's end", () => {
    expect(jointParts("remus-100:waiting + vehicle-2:ABORT")).toEqual([
      ["remus-100", "waiting"],
      ["vehicle-2", "ABORT"],
    ]);
  });
  it("keeps a vehicle id that holds a colon whole", () => {
    expect(jointParts("a:b:COMPLETE + c:ABORT")).toEqual([
      ["a:b", "COMPLETE"],
      ["c", "ABORT"],
    ]);
  });
});
