import { describe, expect, it } from "vitest";

import { statusWords } from "./missionStatus";

const v1 = { version: 1, decision: "approved", record: 1 };
const v2 = { version: 2, decision: "rejected", record: 2 };

describe("mission status with its standing", () => {
  it("never says only Rejected while an earlier version stands approved", () => {
    expect(statusWords("rejected", v1, v2)).toBe("v1 approved; v2 rejected");
    expect(statusWords("approved", v1, v1)).toBe("Approved (v1)");
    expect(statusWords("submitted", v1, v1)).toBe("Submitted; v1 approved");
  });

  it("is the plain status when nothing stands approved", () => {
    expect(statusWords("rejected", null, v2)).toBe("Rejected");
    expect(statusWords("draft", null, null)).toBe("Draft");
  });
});
