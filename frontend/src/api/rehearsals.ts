/** Rehearsal records as a resource: a mission's stored records and one record by digest. */
import { type QueryClient, useQuery } from "@tanstack/react-query";

import { api, unwrap } from "./client";
import { missionKeys } from "./missions";


export const rehearsalKeys = {
  ofMission: (mission: string) => [...missionKeys.one(mission), "rehearsal-records"] as const,
  list: (mission: string, limit: number | null) => [...rehearsalKeys.ofMission(mission), limit] as const,
  record: (digest: string) => ["rehearsal-records", digest] as const,
};

async function listRecords(mission: string, limit: number | null) {
  return unwrap(
    await api.GET("/api/missions/{mission_id}/rehearsal-records", {
      params: { path: { mission_id: mission }, query: limit === null ? {} : { limit } },
    }),
  );
}

/** A stored record as the mission's list shows it. */
export type StoredRecord = Awaited<ReturnType<typeof listRecords>>[number];

/** A mission's records, newest first (`limit` null: as many as the server lists). */
export function useRehearsalRecords(mission: string, limit: number | null, enabled = true) {
  return useQuery({ queryKey: rehearsalKeys.list(mission, limit), enabled, queryFn: () => listRecords(mission, limit) });
}

export function useRehearsalRecord(digest: string) {
  return useQuery({
    queryKey: rehearsalKeys.record(digest),
    queryFn: async () => unwrap(await api.GET("/api/rehearsal-records/{digest}", { params: { path: { digest } } })),
  });
}

/** A rehearsal was stopped and stored: listed at once from the stop's answer (no request), and
 * the other lists of the mission's records marked stale. */
export function rehearsalStored(client: QueryClient, mission: string, stored: StoredRecord): Promise<void> {
  client.setQueryData<StoredRecord[]>(rehearsalKeys.list(mission, null), (old) => [
    stored,
    ...(old ?? []).filter((r) => r.digest !== stored.digest),
  ]);
  return client.invalidateQueries({
    queryKey: rehearsalKeys.ofMission(mission),
    predicate: (q) => q.queryKey.at(-1) !== null,
  });
}
