import { createElement } from "react";
import { renderToStaticMarkup } from "react-dom/server";
import { describe, expect, it } from "vitest";

import type { Schema } from "../../api/client";
import { CampaignResults } from "./CampaignPanel";
import { jointParts } from "./TeamCampaignResults";

type Campaign = Schema<"CampaignOut">;
type Estimate = Schema<"Estimate">;

const estimate = (count: number, p: number | null): Estimate => ({ count, p, ci: [0, 1] });

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

function teamCampaign(end: string): Campaign {
  return {
    id: "0123456789abcdef",
    mission: "m",
    version: 1,
    orders_digest: "sha256:00",
    owner: "operator1",
    spec: { simulations: 2, faults: ["none"], goals: ["start"], seed: 0, chunk: 10 },
    simulations: 2,
    done: 2,
    state: "finished",
    created_at: "2026-12-03T12:00:00Z",
    ended_at: null,
    digest: null,
    error: null,
    results: {
      simulations: 2,
      team: {
        vehicles: ["a", "b"],
        joint: [{ end, count: 2, p: 1, ci: [0.34, 1], possible: false, executions: null }],
        unfinished: estimate(0, 0),
        meetings: [{ meet: "R1", vehicles: ["a", "b"], completed: estimate(0, 0), deadlocked: estimate(2, 1), outcomes: {} }],
        members: [{ vehicle: "a", terminals: { waiting: estimate(2, 1) }, total_paths: 1, covered_paths: 0 }],
        coverage: { checked: true, possible: 1, reached: 0, missed: ["a:COMPLETE + b:COMPLETE"] },
        findings: [{ code: "TEAM", severity: "error", end, count: 2, runs: [0, 1], message: `2 simulations ended at ${end}` }],
      },
    },
  };
}

describe("a team campaign's results", () => {
  it("shows the joint table, the impossible end as a TEAM finding, and text as text", () => {
    const html = renderToStaticMarkup(
      createElement(CampaignResults, { campaign: teamCampaign("a:waiting + <b>x</b>:ABORT"), offer: false }),
    );
    expect(html).toContain('data-testid="joint-table"');
    expect(html).toContain("impossible (TEAM)");
    expect(html).toContain("a: <span class=\"waiting\">left waiting</span>");
    expect(html).toContain("&lt;b&gt;x&lt;/b&gt;");
    expect(html).not.toContain("<b>x</b>");
    expect(html).toContain("Never reached: a:COMPLETE + b:COMPLETE");
  });
});
