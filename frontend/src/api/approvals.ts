/** Signed decisions as a resource: the audit history, one record, its executions, and what a
 * decision or a revocation invalidates. */
import { keepPreviousData, type QueryClient, useQuery } from "@tanstack/react-query";

import { api, type paths, type Schema, unwrap } from "./client";
import { missionKeys } from "./missions";
import { submissionKeys } from "./submissions";

export type ApprovalPage = Schema<"ApprovalPage">;
export type ApprovalQuery = NonNullable<paths["/api/approvals"]["get"]["parameters"]["query"]>;
export type ApprovalDetail = Schema<"ApprovalDetailOut">;
export type RecordExecutions = Schema<"RecordExecutionsOut">;

export const approvalKeys = {
  all: ["approvals"] as const,
  history: (query: ApprovalQuery) => ["approvals", "history", query] as const,
  one: (id: number) => ["approvals", "one", id] as const,
  executions: (id: number) => ["approvals", "one", id, "executions"] as const,
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

export async function loadApproval(id: number): Promise<ApprovalDetail> {
  return unwrap(await api.GET("/api/approvals/{approval_id}", { params: { path: { approval_id: id } } }));
}

export function useApproval(id: number) {
  return useQuery({ queryKey: approvalKeys.one(id), queryFn: () => loadApproval(id) });
}

export function useRecordExecutions(id: number) {
  return useQuery({
    queryKey: approvalKeys.executions(id),
    queryFn: async (): Promise<RecordExecutions> =>
      unwrap(await api.GET("/api/approvals/{approval_id}/executions", { params: { path: { approval_id: id } } })),
  });
}

/** After a decision or a revocation. */
export function approvalsChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: approvalKeys.all });
}

/** A supervisor decided on a version: the records, the submissions, and the mission (its
 * status, standing and review) change. */
export function decisionRecorded(client: QueryClient, mission: string): Promise<unknown> {
  return Promise.all([
    approvalsChanged(client),
    client.invalidateQueries({ queryKey: submissionKeys.all }),
    client.invalidateQueries({ queryKey: missionKeys.one(mission) }),
    client.invalidateQueries({ queryKey: missionKeys.lists }),
  ]);
}

/** A record was revoked: the same reach as a decision (the version no longer stands approved). */
export const recordRevoked = decisionRecorded;
