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

export function useCreateToken() {
  const client = useQueryClient();
  return useMutation({
    mutationFn: async (body: TokenIn) => unwrap(await api.POST("/api/tokens", { body })),
    onSuccess: () => tokensChanged(client),
  });
}

export function useRevokeToken() {
  const client = useQueryClient();
  return useMutation({
    mutationFn: async (id: number) => {
      const result = await api.DELETE("/api/tokens/{token_id}", { params: { path: { token_id: id } } });
      if (!result.response.ok) unwrap(result);
    },
    onSuccess: () => tokensChanged(client),
  });
}
