/** One's own session and password as a resource: signing in and out, and changing the password
 * (which ends the other sessions and revokes every API token). */
import { type QueryClient, useMutation, useQueryClient } from "@tanstack/react-query";

import { api, ApiError, csrf, unwrap } from "./client";
import { tokensChanged } from "./tokens";

export function useSignIn() {
  return useMutation({
    mutationFn: async (body: { username: string; password: string }) => unwrap(await api.POST("/api/auth/login", { body })),
  });
}

/** Sign out: whatever the server answers, this browser forgets the session and what the
 * signed-in person's pages fetched (the next one to sign in starts empty). */
export function signOutMutation(client: QueryClient) {
  return {
    mutationFn: async () => {
      await api.POST("/api/auth/logout");
    },
    onSettled: () => {
      csrf.clear();
      client.clear();
    },
  };
}

export function useSignOut() {
  return useMutation(signOutMutation(useQueryClient()));
}

export function changePasswordMutation(client: QueryClient) {
  return {
    mutationFn: async (body: { current_password: string; new_password: string }) => {
      const result = await api.POST("/api/auth/password", { body });
      if (!result.response.ok) throw new ApiError(result.response.status, result.error);
    },
    onSuccess: () => tokensChanged(client),
  };
}

/** Change my password: my API tokens are revoked with it, so their list is asked for again. */
export function useChangePassword() {
  return useMutation(changePasswordMutation(useQueryClient()));
}
