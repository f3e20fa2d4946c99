import { describe, expect, it } from "vitest";

import type { Report } from "./client";
import { type ReportPrefetch, reportOf } from "./reportPrefetch";

function prefetched(digest: string | null): ReportPrefetch {
  const report = digest === null ? null : ({ digest, ok: true, findings: [] } as unknown as Report);
  return { report, done: Promise.resolve(report) };
}

describe("the report asked for beside the mission", () => {
  it("opens the editor only with the report of the draft it opens", () => {
    expect(reportOf(prefetched("d1"), "d1")?.digest).toBe("d1");
    // A report of other orders (the draft was saved since it was asked for) is not shown.
    expect(reportOf(prefetched("d0"), "d1")).toBeNull();
  });

  it("leaves the editor to ask when nothing came", () => {
    expect(reportOf(prefetched(null), "d1")).toBeNull();
    expect(reportOf(null, "d1")).toBeNull();
    expect(reportOf(undefined, "d1")).toBeNull();
  });
});
