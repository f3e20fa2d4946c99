/** Signed decisions as a resource: the audit history, filtered and paged by cursor. */
import { keepPreviousData, type QueryClient, useQuery } from "@tanstack/react-query";

import { api, type paths, type Schema, unwrap } from "./client";

export type ApprovalPage = Schema<"ApprovalPage">;
export type ApprovalQuery = NonNullable<paths["/api/approvals"]["get"]["parameters"]["query"]>;

export const approvalKeys = {
  all: ["approvals"] as const,
  history: (query: ApprovalQuery) => ["approvals", "history", query] as const,
};

export async function listApprovals(query: ApprovalQuery): Promise<ApprovalPage> {
  return unwrap(await api.GET("/api/approvals", { params: { query } }));
}

export function useApprovalHistory(query: ApprovalQuery) {
  return useQuery({
    queryKey: approvalKeys.history(query),
    queryFn: () => listApprovals(query),
    placeholderData: keepPreviousData,
  });
}

/** After a decision or a revocation. */
export function approvalsChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: approvalKeys.all });
}
