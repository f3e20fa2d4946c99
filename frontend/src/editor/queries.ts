/**
 * The editor's server state through TanStack Query: the saved draft's report, the plain orders
 * as saved, and what a saved draft invalidates. Keys sit inside the missions' and the reports'
 * (api/), so a write anywhere that invalidates a mission reaches these too. The edits' own checks
 * (/api/validate, one per edit) stay in useServerCheck: they report orders not yet saved.
 */
import { type QueryClient, useQuery } from "@tanstack/react-query";

import { exportHref, fetchText, type MissionDetail, type Report } from "../api/client";
import { missionKeys } from "../api/missions";
import { type ReportPrefetch, reportOf } from "../api/reportPrefetch";
import { fetchReport, reportKeys } from "../api/reports";

/** The saved draft's report is the newest one, kept apart from the reports keyed by a digest. */
export const editorKeys = {
  mission: missionKeys.detail,
  report: (id: string) => [...reportKeys.mission(id), "saved"] as const,
  plain: (id: string) => [...missionKeys.one(id), "plain"] as const,
};

/** The saved draft's report, fresh (after a save or a reload of theirs) or from the cache. */
export function fetchSavedReport(client: QueryClient, id: string, fresh = false): Promise<Report> {
  return client.fetchQuery({ queryKey: editorKeys.report(id), queryFn: () => fetchReport(id), staleTime: fresh ? 0 : Infinity });
}

/** The report the page asked for beside the mission, if it is of the opened draft (its digest),
 * is put in the cache, so that the editor opens with its findings and asks for none. */
export function seedOpening(client: QueryClient, mission: MissionDetail, prefetch: ReportPrefetch | null | undefined): Promise<Report | null> | null {
  const ready = reportOf(prefetch, mission.draft_digest);
  if (ready) client.setQueryData(editorKeys.report(mission.id), ready);
  client.setQueryData(editorKeys.mission(mission.id), mission);
  if (ready || !prefetch) return null;
  return prefetch.done.then(() => {
    const late = reportOf(prefetch, mission.draft_digest);
    if (late) client.setQueryData(editorKeys.report(mission.id), late);
    return late;
  });
}

/** The plain-language orders as saved: asked for only while their tab is open (`enabled`);
 * a save invalidates them (draftSaved in api/missions.ts), so an open tab shows the new text. */
export function usePlainOrders(id: string, enabled: boolean) {
  return useQuery({ queryKey: editorKeys.plain(id), queryFn: () => fetchText(exportHref(id, "plain")), enabled });
}
