/** Missions as a resource: the list, one mission and what hangs off its draft (plain orders,
 * paths, standing), their keys, and what a write to a mission invalidates. */
import { keepPreviousData, type QueryClient, useQuery } from "@tanstack/react-query";

import { api, exportHref, fetchText, type MissionDetail, type MissionPage, type PathPage, unwrap } from "./client";
import { reportKeys } from "./reports";

export interface MissionQuery {
  limit: number;
  q?: string;
  status?: string;
  cursor?: string;
}

// Everything of one mission is under ["missions", id] so that one invalidation reaches it all;
// the draft's digest is in the keys of what the draft decides (a new draft, new answers).
export const missionKeys = {
  all: ["missions"] as const,
  lists: ["missions", "list"] as const,
  list: (query: MissionQuery) => ["missions", "list", query] as const,
  one: (id: string) => ["missions", "one", id] as const,
  detail: (id: string) => ["missions", "one", id, "detail"] as const,
  orders: (id: string, digest: string) => ["missions", "one", id, "orders", digest] as const,
  paths: (id: string, digest: string, cursor: string | null) => ["missions", "one", id, "paths", digest, cursor] as const,
  standing: (id: string, status: string) => ["missions", "one", id, "standing", status] as const,
};

const missionPath = (id: string) => ({ params: { path: { mission_id: id } } });

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

export function useMission(id: string) {
  return useQuery({
    queryKey: missionKeys.detail(id),
    queryFn: async () => unwrap(await api.GET("/api/missions/{mission_id}", missionPath(id))),
  });
}

/** The draft's orders in plain language (the export the orders tab shows). */
export function usePlainOrders(id: string, digest: string) {
  return useQuery({ queryKey: missionKeys.orders(id, digest), queryFn: () => fetchText(exportHref(id, "plain")) });
}

/** One page of the draft's paths; the page shown stays while the next loads. */
export function useMissionPaths(id: string, digest: string, cursor: string | null, limit: number) {
  return useQuery({
    queryKey: missionKeys.paths(id, digest, cursor),
    queryFn: async () => {
      const query: { limit: number; cursor?: string } = { limit };
      if (cursor) query.cursor = cursor;
      const result = await api.GET("/api/missions/{mission_id}/paths", { params: { path: { mission_id: id }, query } });
      return unwrap(result) as PathPage; // JSON was asked for (the route can also stream text)
    },
    placeholderData: keepPreviousData,
  });
}

/** What stands approved of a mission; asked again when its status changes. */
export function useStanding(id: string, status: string) {
  return useQuery({
    queryKey: missionKeys.standing(id, status),
    queryFn: async () => unwrap(await api.GET("/api/missions/{mission_id}/standing", missionPath(id))),
  });
}

/** After a mission, a draft or a vehicle that drafts use was saved: lists show the new state. */
export function missionsChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: missionKeys.all });
}

/** The editor saved and was answered with the mission as it now is: shown at once with no
 * request; the lists are marked stale but not asked for (the editor saves as one types). */
export function missionSaved(client: QueryClient, mission: MissionDetail): Promise<void> {
  client.setQueryData(missionKeys.detail(mission.id), mission);
  return client.invalidateQueries({ queryKey: missionKeys.lists, refetchType: "none" });
}

/** The draft was saved, a version created or the mission otherwise changed: all of it (detail,
 * versions, standing, its report) and the lists are asked for again. */
export function missionChanged(client: QueryClient, id: string): Promise<unknown> {
  return Promise.all([
    client.invalidateQueries({ queryKey: missionKeys.one(id) }),
    client.invalidateQueries({ queryKey: missionKeys.lists }),
    client.invalidateQueries({ queryKey: reportKeys.mission(id) }),
  ]);
}
