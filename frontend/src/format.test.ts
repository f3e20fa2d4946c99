import { describe, expect, it } from "vitest";

import { formatDateTime, plural, shortDigest, statusLabel } from "./format";
import { outcomeLetters, traceText } from "./trace";
import { contentTypeFor } from "./upload";

describe("formatting", () => {
  it("formats times as date and minutes in the given zone", () => {
    expect(formatDateTime("2026-11-28T07:43:59Z", "UTC")).toBe("2026-11-28 07:43");
    expect(formatDateTime("not a date")).toBe("not a date");
    expect(formatDateTime(null)).toBe("");
  });

  it("shortens digests and counts", () => {
    expect(shortDigest("sha256:69c9ac488e6fa48089a0489ca17e")).toBe("sha256:69c9ac488e6f…");
    expect(plural(1, "path")).toBe("1 path");
    expect(plural(75, "path")).toBe("75 paths");
    expect(statusLabel("in_review")).toBe("In review");
  });
});

describe("traceText", () => {
  const orders = {
    goals: [
      { id: "G1", title: "Search Area A" },
      { id: "G4", title: "Rendezvous with vehicle 2 in Area C" },
      { id: "G5", title: "Return to Base." },
    ],
  };

  it("words a path as seed 000 Figure 6 does", () => {
    const path = {
      index: 1,
      goals: ["G1", "G4", "G5"],
      outcomes: ["violate", "violate", "violate"],
      terminal: "ABORT",
    };
    expect(traceText(path, orders)).toBe(
      [
        "Ethical Mission Execution Trace #1:",
        "?- execute_mission.",
        "Commence: Search Area A.",
        "Did goal Succeed (s), Fail (f), or end with a Constraint (c)? constraint.",
        "Commence: Rendezvous with vehicle 2 in Area C.",
        "Did goal Succeed (s), Fail (f), or end with a Constraint (c)? constraint.",
        "Commence: Return to Base.",
        "Did goal Succeed (s), Fail (f), or end with a Constraint (c)? constraint.",
        "Mission Abort!",
      ].join("\n"),
    );
    expect(outcomeLetters(path.outcomes)).toBe("c c c");
  });

  it("uses the kinds of declared terminals", () => {
    const path = { index: 2, goals: ["G5"], outcomes: ["succeed"], terminal: "HOME" };
    const text = traceText(path, { ...orders, terminals: [{ id: "HOME", kind: "complete" }] });
    expect(text.split("\n").at(-1)).toBe("Mission Complete!");
  });
});

describe("uploads", () => {
  it("picks the content type of an orders document", () => {
    expect(contentTypeFor("m.JSON")).toBe("application/json");
    expect(contentTypeFor("SailorOverboard.xml")).toBe("application/xml");
    expect(contentTypeFor("meo.ttl")).toBe("text/turtle");
    expect(contentTypeFor("", "", "  @prefix meo: <x#> .")).toBe("text/turtle");
  });
});
