/**
 * The editor's server state through TanStack Query: the saved draft's report, the plain orders
 * as saved, and what a saved draft invalidates. Keys start with the missions' ("missions"), so a
 * write anywhere that invalidates the missions reaches these too. The edits' own checks
 * (/api/validate, one per edit) stay in useServerCheck: they report orders not yet saved.
 */
import { type QueryClient, useQuery } from "@tanstack/react-query";

import { api, exportHref, fetchText, type MissionDetail, type Report, unwrap } from "../api/client";
import { missionsChanged } from "../api/missions";
import { type ReportPrefetch, reportOf } from "../api/reportPrefetch";

export const editorKeys = {
  mission: (id: string) => ["missions", "detail", id] as const,
  report: (id: string) => ["missions", "detail", id, "report"] as const,
  plain: (id: string) => ["missions", "detail", id, "plain"] as const,
};

async function savedReport(id: string): Promise<Report> {
  return unwrap(await api.GET("/api/missions/{mission_id}/report", { params: { path: { mission_id: id } } }));
}

/** The saved draft's report, fresh (after a save or a reload of theirs) or from the cache. */
export function fetchSavedReport(client: QueryClient, id: string, fresh = false): Promise<Report> {
  return client.fetchQuery({ queryKey: editorKeys.report(id), queryFn: () => savedReport(id), staleTime: fresh ? 0 : Infinity });
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
 * a save invalidates them (draftSaved), so an open tab shows the new text. */
export function usePlainOrders(id: string, enabled: boolean) {
  return useQuery({ queryKey: editorKeys.plain(id), queryFn: () => fetchText(exportHref(id, "plain")), enabled });
}

/** A saved draft (mine, or theirs reloaded): the mission's cache holds it as the server answered,
 * and the mission list and this mission's queries are asked for again when next shown. */
export function draftSaved(client: QueryClient, saved: MissionDetail): Promise<void> {
  client.setQueryData(editorKeys.mission(saved.id), saved);
  return missionsChanged(client);
}
