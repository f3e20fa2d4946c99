/** Accounts as a resource (admins): the list, and the writes that change it. */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import type { components } from "./schema";
import { api, unwrap, type User, type UserList } from "./client";

export const userKeys = { all: ["users"] as const };

export async function listUsers(): Promise<UserList> {
  return unwrap(await api.GET("/api/users"));
}

export function useUsers() {
  return useQuery({ queryKey: userKeys.all, queryFn: listUsers });
}

export function usersChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: userKeys.all });
}

type UserPatch = components["schemas"]["UserPatch"];

/** Change an account (enable or disable it, its role, a password reset); the list is asked for again after it. */
export function updateUserMutation(client: QueryClient) {
  return {
    mutationFn: async ({ user, patch }: { user: User; patch: UserPatch }) =>
      unwrap(await api.PATCH("/api/users/{user_id}", { params: { path: { user_id: user.id } }, body: patch })),
    onSuccess: () => usersChanged(client),
  };
}

export function useUpdateUser() {
  return useMutation(updateUserMutation(useQueryClient()));
}

type NewUser = components["schemas"]["UserIn"];

/** Create an account; the list is asked for again after it. */
export function createUserMutation(client: QueryClient) {
  return {
    mutationFn: async (body: NewUser) => unwrap(await api.POST("/api/users", { body })),
    onSuccess: () => usersChanged(client),
  };
}

export function useCreateUser() {
  return useMutation(createUserMutation(useQueryClient()));
}
