/** Submissions as a resource: the reviews list, and what a decision or a submit invalidates. */
import { type QueryClient, useQuery } from "@tanstack/react-query";

import { api, type Schema, unwrap } from "./client";

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
