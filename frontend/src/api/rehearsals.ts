/** Rehearsal records as a resource: a mission's stored records and one record by digest. */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import { api, type paths, unwrap } from "./client";
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

type StartIn = NonNullable<paths["/api/missions/{mission_id}/rehearsals"]["post"]["requestBody"]>["content"]["application/json"];
type Outcome = NonNullable<paths["/api/rehearsals/{rehearsal_id}/outcome"]["post"]["requestBody"]>["content"]["application/json"]["outcome"];

/** What the page asks of a live rehearsal: start one, answer its question, skip to the next
 * decision or inject a fault. */
export type RehearsalCommand =
  | { start: StartIn }
  | { rehearsal: string; outcome: Outcome }
  | { rehearsal: string; skip: true }
  | { rehearsal: string; fault: string };

async function sendCommand(mission: string, command: RehearsalCommand) {
  if ("start" in command) {
    return unwrap(await api.POST("/api/missions/{mission_id}/rehearsals", { params: { path: { mission_id: mission } }, body: command.start }));
  }
  const path = { params: { path: { rehearsal_id: command.rehearsal } } };
  if ("outcome" in command) return unwrap(await api.POST("/api/rehearsals/{rehearsal_id}/outcome", { ...path, body: { outcome: command.outcome } }));
  if ("fault" in command) return unwrap(await api.POST("/api/rehearsals/{rehearsal_id}/faults", { ...path, body: { fault: command.fault } }));
  return unwrap(await api.POST("/api/rehearsals/{rehearsal_id}/skip", path));
}

/** A live rehearsal's state as the command answered it. It lives in the page that runs it (it
 * is in one server process): no query of the cache holds it, so nothing is invalidated. */
export function useRehearsalCommand(mission: string) {
  return useMutation({ mutationFn: (command: RehearsalCommand) => sendCommand(mission, command) });
}

export function stopRehearsalMutation(client: QueryClient, mission: string) {
  return {
    mutationFn: async (rehearsal: string): Promise<StoredRecord> =>
      unwrap(await api.POST("/api/rehearsals/{rehearsal_id}/stop", { params: { path: { rehearsal_id: rehearsal } } })),
    onSuccess: (stored: StoredRecord) => rehearsalStored(client, mission, stored),
  };
}

/** Stop a rehearsal and store its record: listed at once from the stop's answer. */
export function useStopRehearsal(mission: string) {
  return useMutation(stopRehearsalMutation(useQueryClient(), mission));
}
