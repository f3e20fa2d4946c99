/** One's own API tokens as a resource: listed, created (the secret shown once) and revoked. */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import { api, type Schema, unwrap } from "./client";

export type TokenIn = Schema<"TokenIn">;

export const tokenKeys = { all: ["tokens"] as const };

export function useTokens() {
  return useQuery({ queryKey: tokenKeys.all, queryFn: async () => unwrap(await api.GET("/api/tokens")) });
}

/** After a token was made or revoked, or a password change revoked them all. */
export function tokensChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: tokenKeys.all });
}

/** Create a token (its secret is in the answer, shown once); the list is asked for again after it. */
export function createTokenMutation(client: QueryClient) {
  return {
    mutationFn: async (body: TokenIn) => unwrap(await api.POST("/api/tokens", { body })),
    onSuccess: () => tokensChanged(client),
  };
}

export function useCreateToken() {
  return useMutation(createTokenMutation(useQueryClient()));
}

/** Revoke a token by its id (the answer has no body); the list is asked for again after it. */
export function revokeTokenMutation(client: QueryClient) {
  return {
    mutationFn: async (id: number) => {
      const result = await api.DELETE("/api/tokens/{token_id}", { params: { path: { token_id: id } } });
      if (!result.response.ok) unwrap(result);
    },
    onSuccess: () => tokensChanged(client),
  };
}

export function useRevokeToken() {
  return useMutation(revokeTokenMutation(useQueryClient()));
}
