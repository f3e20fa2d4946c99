import { describe, expect, it } from "vitest";

import { gridColumns, gridWidth, pathSentence, pathSteps, titlesOf } from "./pathGrid";

const orders = {
  goals: [
    { id: "G1", title: "Transit" },
    { id: "G2", title: "<b>Search</b>" },
  ],
  terminals: [{ id: "ABORT", title: "Abort the mission" }],
};
const path = { index: 4, goals: ["G1", "G2"], outcomes: ["succeed", "violate"], terminal: "ABORT" };

describe("path rows", () => {
  it("give each step its goal id, title and outcome letter", () => {
    expect(pathSteps(path, titlesOf(orders))).toEqual([
      { goal: "G1", title: "Transit", outcome: "succeed", letter: "s" },
      { goal: "G2", title: "<b>Search</b>", outcome: "violate", letter: "c" },
    ]);
  });
  it("read as one sentence", () => {
    expect(pathSentence(path, titlesOf(orders))).toBe(
      "Path 4: G1 Transit, succeeds; G2 <b>Search</b>, constraint violated; then ABORT Abort the mission.",
    );
  });
  it("share one column template, so that step k lines up in every row", () => {
    expect(gridColumns(3)).toBe("64px repeat(3, 168px) 184px");
    expect(gridWidth(3)).toBe(64 + 3 * 168 + 184);
    expect(gridColumns(0)).toBe(gridColumns(1));
  });
});

describe("titles of refined goals", () => {
  it("names nested steps and their unrolled copies by the goal they copy", () => {
    const titles = titlesOf({
      goals: [{ id: "G1", title: "Search", refines: { goals: [{ id: "G1.1", title: "Next cell" }], terminals: [{ id: "T", title: "Found" }] } }],
    });
    expect(titles.get("G1/G1.1")).toBe("Next cell");
    expect(titles.get("G1/T")).toBe("Found");
    const steps = pathSteps({ index: 1, goals: ["G1/G1.1#2", "G1/G1.1@600s"], outcomes: ["fail", "succeed"], terminal: "C" }, titles);
    expect(steps.map((s) => s.title)).toEqual(["Next cell", "Next cell"]);
  });
});
