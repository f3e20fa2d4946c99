import { createElement } from "react";
import { renderToStaticMarkup } from "react-dom/server";
import { describe, expect, it } from "vitest";

import type { Schema } from "../../api/client";
import { CampaignResults, notReached, percent } from "./CampaignPanel";

type Campaign = Schema<"CampaignOut">;
type Estimate = Schema<"Estimate">;

const estimate = (count: number, p: number | null, ci: number[]): Estimate => ({ count, p, ci });

function campaign(results: Campaign["results"]): Campaign {
  return {
    id: "0123456789abcdef",
    mission: "m",
    version: 1,
    orders_digest: "sha256:00",
    owner: "operator1",
    spec: { simulations: 4, faults: ["none"], goals: ["start"], seed: 0, chunk: 10 },
    simulations: 4,
    done: results ? 4 : 1,
    state: results ? "finished" : "running",
    created_at: "2026-12-03T12:00:00Z",
    ended_at: null,
    digest: null,
    error: null,
    results,
  };
}

function results(complete: Estimate): NonNullable<Campaign["results"]> {
  const none = estimate(0, 0, [0, 0.49]);
  return {
    simulations: 4,
    terminals: { COMPLETE: complete },
    kinds: { complete },
    no_terminal: none,
    any_violation: none,
    goals: {},
    coverage: { total_paths: 3, covered: 1, paths: [{ path: 1, count: 4 }] },
    energy_wh: { mean: 1, min: 1, max: 1, histogram: { edges: [0, 1], counts: [4] } },
  };
}

const render = (c: Campaign) => renderToStaticMarkup(createElement(CampaignResults, { campaign: c, offer: false }));

describe("a campaign's results", () => {
  it("says so when there are no results yet", () => {
    const html = render(campaign(null));
    expect(html).toContain("This campaign has no results yet.");
    expect(html).not.toContain("<table");
  });

  it("shows the estimate and its interval as percentages", () => {
    const html = render(campaign(results(estimate(4, 1, [0.51, 1]))));
    expect(html).toContain("100.0%");
    expect(html).toContain("51.0% – 100.0%");
  });

  it("shows a missing bound as a dash, not NaN%", () => {
    const html = render(campaign(results(estimate(4, 1, [0.51]))));
    expect(html).toContain("51.0% – —");
    expect(html).not.toContain("NaN");
  });
});

describe("percent", () => {
  it("is a dash for no number and for a number that is not one", () => {
    expect(percent(null)).toBe("—");
    expect(percent(Number.NaN)).toBe("—");
    expect(percent(0.125)).toBe("12.5%");
  });
});

describe("paths a campaign did not reach", () => {
  it("lists the first ones by number and counts the rest", () => {
    expect(notReached([1, 3], 5)).toEqual({ first: [2, 4, 5], more: 0 });
    expect(notReached([2], 100, 3)).toEqual({ first: [1, 3, 4], more: 96 });
    expect(notReached([1], null)).toBeNull();
    expect(notReached([1, 2], 2)).toEqual({ first: [], more: 0 });
  });
});
