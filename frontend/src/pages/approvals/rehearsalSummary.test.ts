/** A team's rehearsal record in the review's summary: each member's runs labelled with its
 * vehicle and the joint end, not the empty single-run fields of the team. */
import { describe, expect, it } from "vitest";

import { summaryRows } from "./RehearsalSummary";

type Record = Parameters<typeof summaryRows>[0];

const run = (terminal: string, path: number | null = null) => ({ path_index: path, goals: ["G1"], outcomes: ["succeed"], terminal, terminal_kind: "complete" });

describe("summaryRows", () => {
  it("labels each member's run with its vehicle and ends with the joint end", () => {
    const record = {
      runs: [run("COMPLETE"), run("ABORT", 19)], goals: [], outcomes: [], terminal: null, terminal_kind: null,
      team: { joint_end: "remus-100:waiting + vehicle-2:ABORT", members: [{ vehicle: "remus-100", runs: [run("COMPLETE")] }, { vehicle: "vehicle-2", runs: [run("ABORT", 19)] }] },
    } as unknown as Record;
    const { ended, rows } = summaryRows(record);
    expect(ended).toBe("the joint end remus-100:waiting + vehicle-2:ABORT");
    expect(rows.map((r) => [r.label, r.run.terminal, r.run.path_index])).toEqual([["remus-100", "COMPLETE", null], ["vehicle-2", "ABORT", 19]]);
  });

  it("reads one vehicle's record as before", () => {
    const record = { runs: [], goals: ["G1"], outcomes: ["succeed"], terminal: "COMPLETE", terminal_kind: "complete", team: null } as unknown as Record;
    const { ended, rows } = summaryRows(record);
    expect(ended).toBe("COMPLETE (complete)");
    expect(rows.map((r) => r.label)).toEqual(["Path"]);
  });
});
