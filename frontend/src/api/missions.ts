/** Missions as a resource: the list's query, its key, and what a write to a mission invalidates. */
import { keepPreviousData, type QueryClient, useQuery } from "@tanstack/react-query";

import { api, type MissionPage, unwrap } from "./client";

export interface MissionQuery {
  limit: number;
  q?: string;
  status?: string;
  cursor?: string;
}

export const missionKeys = {
  all: ["missions"] as const,
  list: (query: MissionQuery) => ["missions", "list", query] as const,
};

export async function listMissions(query: MissionQuery): Promise<MissionPage> {
  return unwrap(await api.GET("/api/missions", { params: { query } }));
}

/** One page of the mission list; the previous page stays shown while the next loads. */
export function useMissionList(query: MissionQuery) {
  return useQuery({
    queryKey: missionKeys.list(query),
    queryFn: () => listMissions(query),
    placeholderData: keepPreviousData,
  });
}

/** After a mission, a draft or a vehicle that drafts use was saved: lists show the new state. */
export function missionsChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: missionKeys.all });
}
