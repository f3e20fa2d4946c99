/**
 * The saved draft's report, asked for beside the mission when the graph editor is opened (not
 * after the editor mounted): the editor then opens with its findings. Asked for after mounting,
 * it came back while the canvas was being laid out and made React render every node a second
 * time (their markers) and the findings list, just after the canvas said ready. It goes through
 * reports.ts (one place asks for `/report`) and lands in the query cache the findings tab reads.
 */
import type { Report } from "./client";
import { queryClient } from "./query";
import { loadReport } from "./reports";

export interface ReportPrefetch {
  /** The report once it has come, else null. */
  report: Report | null;
  /** The report, or null should it fail (the editor then asks again itself). */
  done: Promise<Report | null>;
}

export function prefetchReport(missionId: string): ReportPrefetch {
  const prefetch: ReportPrefetch = { report: null, done: Promise.resolve(null) };
  prefetch.done = loadReport(queryClient, missionId)
    .then((report) => (prefetch.report = report))
    .catch(() => null);
  return prefetch;
}

/** The prefetched report if it is of the draft the editor opens (the digest names the orders). */
export function reportOf(prefetch: ReportPrefetch | null | undefined, draftDigest: string): Report | null {
  const report = prefetch?.report;
  return report && report.digest === draftDigest ? report : null;
}
