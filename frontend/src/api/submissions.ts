/** Submissions as a resource: the reviews list, and what a decision or a submit invalidates. */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import { api, type Schema, unwrap } from "./client";
import { missionKeys } from "./missions";

export type Submission = Schema<"SubmissionOut">;

export const submissionKeys = {
  all: ["submissions"] as const,
  list: (limit: number) => ["submissions", "list", limit] as const,
};

export async function listSubmissions(limit: number): Promise<Submission[]> {
  return unwrap(await api.GET("/api/submissions", { params: { query: { limit } } }));
}

export function useSubmissions(limit: number) {
  return useQuery({ queryKey: submissionKeys.list(limit), queryFn: () => listSubmissions(limit) });
}

/** After a submit, a withdrawal or a decision. */
export function submissionsChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: submissionKeys.all });
}

/** A version was submitted or a submission withdrawn, or evidence attached to one: the
 * submissions and the mission (status, versions' reviews) change. */
export function submissionChanged(client: QueryClient, mission: string): Promise<unknown> {
  return Promise.all([
    submissionsChanged(client),
    client.invalidateQueries({ queryKey: missionKeys.one(mission) }),
    client.invalidateQueries({ queryKey: missionKeys.lists }),
  ]);
}

/** Submit a version for review, or withdraw a submission: either changes the mission. */
export function submissionMutation(client: QueryClient, mission: string) {
  return {
    mutationFn: async (what: { submit: number } | { withdraw: number }) => {
      if ("submit" in what) {
        unwrap(
          await api.POST("/api/missions/{mission_id}/versions/{number}/submit", {
            params: { path: { mission_id: mission, number: what.submit } },
          }),
        );
      } else {
        unwrap(await api.POST("/api/submissions/{submission_id}/withdraw", { params: { path: { submission_id: what.withdraw } } }));
      }
    },
    onSuccess: () => submissionChanged(client, mission),
  };
}

export function useSubmission(mission: string) {
  return useMutation(submissionMutation(useQueryClient(), mission));
}

/** Attach a stored rehearsal record (by digest) to a submission. */
export function attachRehearsalMutation(client: QueryClient, mission: string, submission: number) {
  return {
    mutationFn: async (digest: string) =>
      unwrap(
        await api.POST("/api/submissions/{submission_id}/rehearsal", {
          params: { path: { submission_id: submission } },
          body: { rehearsal: digest },
        }),
      ),
    onSuccess: () => submissionChanged(client, mission),
  };
}

export function useAttachRehearsal(mission: string, submission: number) {
  return useMutation(attachRehearsalMutation(useQueryClient(), mission, submission));
}
