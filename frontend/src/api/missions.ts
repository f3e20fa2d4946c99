/** Missions as a resource: the list, one mission and what hangs off its draft (plain orders,
 * paths, standing), their keys, and what a write to a mission invalidates. */
import { keepPreviousData, MutationObserver, type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";
import { useState } from "react";

import { ApiError, api, exportHref, fetchText, type Finding, type MissionDetail, type MissionPage, type PathPage, type Schema, unwrap } from "./client";
import { reportKeys } from "./reports";
import { contentTypeFor } from "../upload";

type Orders = Schema<"Orders">;
type Layout = MissionDetail["layout"];

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

/** The draft, or the mission as a whole, changed under the editor (mine saved or theirs
 * reloaded): the mission's cache holds it as the server answered, and every mission query and
 * its reports are asked for again when next shown. */
export function draftSaved(client: QueryClient, saved: MissionDetail): Promise<void> {
  client.setQueryData(missionKeys.detail(saved.id), saved);
  return Promise.all([missionsChanged(client), client.invalidateQueries({ queryKey: reportKeys.mission(saved.id) })]).then(() => undefined);
}

/** A new mission: it is shown at once when opened, and the lists hold it when next shown. */
export function missionCreated(client: QueryClient, mission: MissionDetail): Promise<void> {
  client.setQueryData(missionKeys.detail(mission.id), mission);
  return client.invalidateQueries({ queryKey: missionKeys.lists });
}

/** Reads a file into orders on the server (POST /api/read stores nothing), with what reading it found. */
export async function readOrdersFile(file: Blob & { name?: string; type: string }): Promise<{ orders: Orders; findings: Finding[] }> {
  const result = await api.POST("/api/read", {
    body: file as never,
    bodySerializer: (raw: unknown) => raw as BodyInit,
    headers: { "Content-Type": contentTypeFor(file.name ?? "", file.type) },
  });
  const data = unwrap(result);
  return { orders: data.orders as Orders, findings: data.findings ?? [] };
}

export function createMissionMutation(client: QueryClient) {
  return {
    mutationFn: async (orders: Orders) => unwrap(await api.POST("/api/missions", { body: orders })),
    onSuccess: (mission: MissionDetail) => missionCreated(client, mission),
  };
}

/** Create a mission from orders (an empty one, an example's, a plan's). */
export function useCreateMission() {
  return useMutation(createMissionMutation(useQueryClient()));
}

/** Import a file's bytes as they are (JSON, AVCL XML or MEO Turtle) as a new mission. */
export function importMissionMutation(client: QueryClient) {
  return {
    mutationFn: async ({ body, contentType }: { body: string | Blob; contentType: string }) =>
      unwrap(
        await api.POST("/api/import", {
          body: body as never,
          bodySerializer: (raw: unknown) => raw as BodyInit,
          headers: { "Content-Type": contentType },
        }),
      ),
    onSuccess: (mission: MissionDetail) => missionCreated(client, mission),
  };
}

export function useImportMission() {
  return useMutation(importMissionMutation(useQueryClient()));
}

/** A draft save's answer: the mission as saved, or (412) the mission someone else saved first. */
export type DraftSave = { saved: MissionDetail; theirs?: undefined } | { saved?: undefined; theirs: MissionDetail };

async function putDraft(id: string, revision: number, orders: Orders): Promise<DraftSave> {
  const result = await api.PUT("/api/missions/{mission_id}/draft", {
    params: { path: { mission_id: id }, header: { "if-match": `"${revision}"` } },
    body: { orders },
  });
  if (result.response.status === 412) {
    return { theirs: unwrap(await api.GET("/api/missions/{mission_id}", missionPath(id))) };
  }
  return { saved: unwrap(result) };
}

export function saveDraftMutation(client: QueryClient, id: string) {
  return {
    mutationFn: ({ revision, orders }: { revision: number; orders: Orders }) => putDraft(id, revision, orders),
    onSuccess: (answer: DraftSave) => (answer.saved ? draftSaved(client, answer.saved) : undefined),
  };
}

/** Save the draft with If-Match: a conflict (412) answers with their mission and changes nothing. */
export function useSaveDraft(id: string) {
  return useMutation(saveDraftMutation(useQueryClient(), id));
}

/** Save the editor's node positions (editor data: no revision, no "Updated by"). */
export function saveLayoutMutation(client: QueryClient, id: string) {
  return {
    mutationFn: async (layout: Layout) => {
      unwrap(await api.PUT("/api/missions/{mission_id}/layout", { params: { path: { mission_id: id } }, body: { layout } }));
      return layout;
    },
    // The positions are the open editor's own: the cached mission is marked stale (asked for
    // when next opened) rather than replaced, which would re-render the page and the editor.
    onSuccess: () => client.invalidateQueries({ queryKey: missionKeys.detail(id), refetchType: "none" }),
  };
}

export interface DraftSaves {
  saveDraft: (draft: { revision: number; orders: Orders }) => Promise<DraftSave>;
  saveLayout: (layout: Layout) => Promise<Layout>;
}

/** The editor's saves, as the mutations above that the editor does not subscribe to: it shows
 * their state from its own store, and a render of the whole editor for each pending and
 * settled save would cost more than the save. */
export function useDraftSaves(id: string): DraftSaves {
  const client = useQueryClient();
  const [saves] = useState((): DraftSaves => {
    const draft = new MutationObserver(client, saveDraftMutation(client, id));
    const layout = new MutationObserver(client, saveLayoutMutation(client, id));
    return { saveDraft: (d) => draft.mutate(d), saveLayout: (l) => layout.mutate(l) };
  });
  return saves;
}

/** Create a version of the draft: the mission's versions, status and lists change. */
export function createVersionMutation(client: QueryClient, id: string) {
  return {
    mutationFn: async () => unwrap(await api.POST("/api/missions/{mission_id}/versions", missionPath(id))),
    onSuccess: () =>
      Promise.all([
        client.invalidateQueries({ queryKey: missionKeys.one(id) }),
        client.invalidateQueries({ queryKey: missionKeys.lists }),
      ]),
  };
}

export function useCreateVersion(id: string) {
  return useMutation(createVersionMutation(useQueryClient(), id));
}

/** Delete a mission that has no versions: it leaves the cache and the lists. */
export function deleteMissionMutation(client: QueryClient, id: string) {
  return {
    mutationFn: async () => {
      const result = await api.DELETE("/api/missions/{mission_id}", missionPath(id));
      if (!result.response.ok) throw new ApiError(result.response.status, result.error);
    },
    onSuccess: () => {
      client.removeQueries({ queryKey: missionKeys.one(id) });
      return client.invalidateQueries({ queryKey: missionKeys.lists });
    },
  };
}

export function useDeleteMission(id: string) {
  return useMutation(deleteMissionMutation(useQueryClient(), id));
}

/** Ask for the mission and all of it again (after a conflict, to edit the draft now saved). */
export function useReloadMission(id: string): () => void {
  const client = useQueryClient();
  return () => void missionChanged(client, id);
}
