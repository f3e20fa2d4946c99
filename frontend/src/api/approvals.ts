/** Signed decisions as a resource: the audit history, one record, its executions, and what a
 * decision or a revocation invalidates. */
import { keepPreviousData, type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

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

/** The statement the server prepared for signing, signed in the browser into a DSSE envelope. */
export type Prepared = Schema<"PreparedOut">;
export type SignStatement = (prepared: Prepared) => Promise<string>;

export interface DecisionIn {
  decision: "approved" | "rejected";
  reason: string;
  keyId: string;
  password: string;
  /** Checks that the prepared statement says what the review showed, and signs it. */
  sign: SignStatement;
}

/** Decide on a submission: the server prepares the statement, the browser signs it, the server
 * records the signed decision (checking the password with it). */
export function decideMutation(client: QueryClient, mission: string, submission: number) {
  return {
    mutationFn: async ({ decision, reason, keyId, password, sign }: DecisionIn) => {
      const submissionPath = { params: { path: { submission_id: submission } } };
      const prepared = unwrap(await api.POST("/api/submissions/{submission_id}/statement", { ...submissionPath, body: { decision, reason, key_id: keyId } }));
      const envelope = await sign(prepared);
      return unwrap(await api.POST("/api/submissions/{submission_id}/decision", { ...submissionPath, body: { envelope, password } }));
    },
    onSuccess: () => decisionRecorded(client, mission),
  };
}

export function useDecide(mission: string, submission: number) {
  return useMutation(decideMutation(useQueryClient(), mission, submission));
}

export interface RevocationIn {
  reason: string;
  keyId: string;
  password: string;
  sign: SignStatement;
}

/** Revoke an approval with a signed statement, like a decision. */
export function revokeMutation(client: QueryClient, mission: string, approval: number) {
  return {
    mutationFn: async ({ reason, keyId, password, sign }: RevocationIn) => {
      const approvalPath = { params: { path: { approval_id: approval } } };
      const prepared = unwrap(await api.POST("/api/approvals/{approval_id}/statement", { ...approvalPath, body: { reason, key_id: keyId } }));
      const envelope = await sign(prepared);
      return unwrap(await api.POST("/api/approvals/{approval_id}/revoke", { ...approvalPath, body: { envelope, password } }));
    },
    onSuccess: () => recordRevoked(client, mission),
  };
}

export function useRevokeApproval(mission: string, approval: number) {
  return useMutation(revokeMutation(useQueryClient(), mission, approval));
}
