/** Rehearsal campaigns as a resource: a mission's campaigns, one campaign, those attached to a
 * submission; what starting, changing or attaching one invalidates. */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import { api, type paths, type Schema, unwrap } from "./client";
import { missionKeys } from "./missions";
import { useFaultReach } from "./versions";
import { submissionChanged, submissionKeys } from "./submissions";

export type Campaign = Schema<"CampaignOut">;
/** Which goals react to a sweep's faults, asked before a campaign starts. */
export { useFaultReach };

export const campaignKeys = {
  all: ["campaigns"] as const,
  ofMission: (mission: string) => [...missionKeys.one(mission), "campaigns"] as const,
  attached: (submission: number) => [...submissionKeys.all, submission, "campaigns"] as const,
  cited: (submission: number) => [...submissionKeys.all, submission, "cited-campaigns"] as const,
};

export async function missionCampaigns(mission: string): Promise<Campaign[]> {
  return unwrap(await api.GET("/api/missions/{mission_id}/campaigns", { params: { path: { mission_id: mission } } }));
}

/** A mission's campaigns, asked again every second while one runs. */
export function useMissionCampaigns(mission: string, options: { enabled?: boolean; pollWhile?: (c: Campaign[]) => boolean } = {}) {
  return useQuery({
    queryKey: campaignKeys.ofMission(mission),
    queryFn: () => missionCampaigns(mission),
    enabled: options.enabled ?? true,
    refetchInterval: (query) => (options.pollWhile && query.state.data && options.pollWhile(query.state.data) ? 1000 : false),
  });
}

async function attachedCampaigns(submission: number) {
  return unwrap(await api.GET("/api/submissions/{submission_id}/campaigns", { params: { path: { submission_id: submission } } }));
}

export function useAttachedCampaigns(submission: number) {
  return useQuery({ queryKey: campaignKeys.attached(submission), queryFn: () => attachedCampaigns(submission) });
}

/** The campaigns attached to a submission, each in full (records' digests and results). */
export function useCitedCampaignList(submission: number | undefined) {
  return useQuery({
    queryKey: campaignKeys.cited(submission ?? 0),
    enabled: submission !== undefined,
    queryFn: async (): Promise<Campaign[]> => {
      const attached = await attachedCampaigns(submission ?? 0);
      return Promise.all(
        attached.map(async (a) =>
          unwrap(await api.GET("/api/campaigns/{campaign_id}", { params: { path: { campaign_id: a.campaign } } })),
        ),
      );
    },
  });
}

/** A campaign was started, stopped or removed. */
export function campaignsChanged(client: QueryClient, mission: string): Promise<unknown> {
  return Promise.all([
    client.invalidateQueries({ queryKey: campaignKeys.ofMission(mission) }),
    client.invalidateQueries({ queryKey: campaignKeys.all }),
  ]);
}

/** Attach a finished campaign to a submission: the submission and its review cite it now. */
export function attachCampaignMutation(client: QueryClient, mission: string, submission: number) {
  return {
    mutationFn: async (campaign: string) =>
      unwrap(
        await api.POST("/api/submissions/{submission_id}/campaigns", {
          params: { path: { submission_id: submission } },
          body: { campaign },
        }),
      ),
    onSuccess: () => submissionChanged(client, mission),
  };
}

export function useAttachCampaign(mission: string, submission: number) {
  return useMutation(attachCampaignMutation(useQueryClient(), mission, submission));
}

export type CampaignIn = NonNullable<paths["/api/missions/{mission_id}/versions/{number}/campaigns"]["post"]["requestBody"]>["content"]["application/json"];

/** Start a campaign of one version: the mission's campaigns list it (and poll its progress). */
export function startCampaignMutation(client: QueryClient, mission: string) {
  return {
    mutationFn: async ({ version, body }: { version: number; body: CampaignIn }) =>
      unwrap(
        await api.POST("/api/missions/{mission_id}/versions/{number}/campaigns", {
          params: { path: { mission_id: mission, number: version } },
          body,
        }),
      ),
    onSuccess: () => campaignsChanged(client, mission),
  };
}

export function useStartCampaign(mission: string) {
  return useMutation(startCampaignMutation(useQueryClient(), mission));
}

/** Cancel a queued or running campaign of the mission. */
export function cancelCampaignMutation(client: QueryClient, mission: string) {
  return {
    mutationFn: async (campaign: string) =>
      unwrap(await api.POST("/api/campaigns/{campaign_id}/cancel", { params: { path: { campaign_id: campaign } } })),
    onSuccess: () => campaignsChanged(client, mission),
  };
}

export function useCancelCampaign(mission: string) {
  return useMutation(cancelCampaignMutation(useQueryClient(), mission));
}
