import { describe, expect, it } from "vitest";

import { groupFindings, loopsOf } from "./findingGroups";

const f = (code: string, severity: string, subjects: string[], message = `${code} ${subjects.join(" ")}`) => ({ code, severity, subjects, message });

describe("findings grouped for the editor", () => {
  it("lists errors before warnings, whatever the report's order", () => {
    const groups = groupFindings([f("SINK", "warning", ["G1"]), f("G10", "error", ["G4"]), f("TEXT", "warning", ["C1"]), f("M7", "error", ["G2"])]);
    expect(groups.map((g) => g.severity)).toEqual(["error", "error", "warning", "warning"]);
    expect(groups.map((g) => g.code)).toEqual(["G10", "M7", "SINK", "TEXT"]);
  });

  it("shows each loop once: cycles over shared goals are one item with every goal", () => {
    const findings = [
      f("G7", "error", ["A", "B"]),
      f("G7", "error", ["B", "C", "D"]),
      f("G7", "error", ["X", "Y"]),
      f("G7", "error", ["A", "D"]),
    ];
    expect(loopsOf(findings).map((l) => l.goals)).toEqual([["A", "B", "C", "D"], ["X", "Y"]]);
    const [loops] = groupFindings(findings);
    expect(loops!.items).toHaveLength(2);
    expect(loops!.items[0]!.subjects).toEqual(["A", "B", "C", "D"]);
    expect(loops!.items[0]!.findings).toHaveLength(3);
    expect(loops!.items[0]!.message).toMatch(/Loop through 4 goals: 3 cycles/);
    expect(loops!.items[1]!.message).toBe("G7 X Y");
  });
});
