import { describe, expect, it } from "vitest";

import { evidenceText } from "./evidence";

describe("evidenceText", () => {
  it("says what a complete log evidenced", () => {
    expect(evidenceText({ complete: true, timed: true, untimed_steps: [], constraints_read: ["C1", "C7"],
      constraints_unread: [], gaps: [] })).toBe(
      "evidenced: start and end times of every goal run; readings for C1, C7");
  });

  it("names what a log without times or readings did not evidence", () => {
    expect(evidenceText({ complete: false, timed: false, untimed_steps: [1, 2], constraints_read: [],
      constraints_unread: ["C1", "C4"], gaps: ["no start and end times for steps 1, 2", "no readings for C1, C4"] }))
      .toBe("evidenced: nothing; not evidenced: no start and end times for steps 1, 2; no readings for C1, C4");
  });

  it("does not present an entry recorded before evidence was checked as evidenced", () => {
    expect(evidenceText(null)).toMatch(/^evidence not checked/);
  });
});
