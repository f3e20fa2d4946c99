import { describe, expect, it } from "vitest";

import { behaviourChoices, filterChoices, idAndTitle, movesThroughOptions, successorChoices, trustedBehaviours } from "./pickers";

const goals = [
  { id: "G1", title: "Transit to the survey box" },
  { id: "G2", title: "Search the box" },
  { id: "G10", title: "Sample the plume" },
];

describe("goal pickers", () => {
  it("offer every goal and terminal by id and title", () => {
    const choices = successorChoices(goals, [{ id: "COMPLETE", kind: "complete", title: "Mission complete" }]);
    expect(choices.map((c) => c.label)).toEqual([
      "— none —",
      "G1: Transit to the survey box",
      "G2: Search the box",
      "G10: Sample the plume",
      "COMPLETE: Mission complete",
    ]);
  });
  it("find a goal by words of its title, in any case", () => {
    const found = filterChoices(successorChoices(goals, []), "PLUME sample");
    expect(found.map((c) => c.value)).toEqual(["G10"]);
  });
  it("put ids starting with the query first", () => {
    const found = filterChoices(successorChoices(goals, []), "g1");
    expect(found.map((c) => c.value)).toEqual(["G1", "G10"]);
  });
  it("keep all choices for an empty query", () => {
    expect(filterChoices(successorChoices(goals, []), "  ")).toHaveLength(4);
  });
  it("show the id alone when untitled", () => {
    expect(idAndTitle("G3", "")).toBe("G3");
    expect(idAndTitle("G3", "Loiter")).toBe("G3: Loiter");
  });
});

describe("behaviour picker", () => {
  it("offers the trusted behaviours and marks a current one the vehicle lacks", () => {
    const choices = behaviourChoices(["area_search", "transit"], "hover", "auv-1");
    expect(choices.map((c) => c.value)).toEqual(["", "area_search", "transit", "hover"]);
    expect(choices.at(-1)?.detail).toBe("not a trusted behaviour of auv-1");
  });
});

describe("native drop-downs", () => {
  it("treat arrows, paging and type-ahead as moving, not choosing", () => {
    for (const key of ["ArrowDown", "ArrowUp", "Home", "End", "PageDown", "a", "G"]) expect(movesThroughOptions(key)).toBe(true);
    for (const key of ["Enter", "Tab", "Escape", " "]) expect(movesThroughOptions(key)).toBe(false);
    expect(movesThroughOptions("ArrowDown", { altKey: true })).toBe(false);
  });
});

describe("trusted behaviours", () => {
  const features = [{ fulfills: ["area_search", "transit"] }, { fulfills: ["sample", "transit"] }, {}];

  it("are the profile's own list when it gives one", () => {
    expect(trustedBehaviours({ behaviors: ["transit"], features })).toEqual(["transit"]);
  });

  it("are what the features fulfil when the profile lists none (as DESIGN.md writes profiles)", () => {
    expect(trustedBehaviours({ features })).toEqual(["area_search", "transit", "sample"]);
    expect(trustedBehaviours({ behaviors: [], features })).toEqual(["area_search", "transit", "sample"]);
  });

  it("are none when the features fulfil nothing", () => {
    expect(trustedBehaviours({ features: [{ fulfills: [] }] })).toEqual([]);
  });
});
