/** Signing keys as a resource: the server's registered public keys beside the private keys kept
 * in this browser (IndexedDB), and the writes that change both: registering (with rotation) and
 * revoking. A key's two halves change together, so each write does both in one mutation. */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import { deleteKey, generateSigningKey, listKeys, saveKey, type StoredKey } from "../crypto/keystore";
import { api, type Schema, unwrap } from "./client";

export type Key = Schema<"KeyOut">;

export interface KeyRing {
  /** Keys registered and active on the server whose private key is in this browser. */
  usable: StoredKey[];
  /** Every key in this browser for this user and server. */
  local: StoredKey[];
  /** Every key the server knows (supervisors see all supervisors' keys). */
  server: Key[];
  /** Why this browser's keys could not be read (the server's are still listed). */
  localError: unknown;
}

export const keyKeys = {
  all: ["keys"] as const,
  ring: (username: string) => ["keys", username] as const,
};

async function loadKeyRing(username: string): Promise<KeyRing> {
  const server = unwrap(await api.GET("/api/keys")) as Key[];
  let local: StoredKey[] = [];
  let localError: unknown = null;
  try {
    local = await listKeys(username);
  } catch (e) {
    localError = e;
  }
  const active = new Set(server.filter((k) => k.status === "active" && k.user === username).map((k) => k.key_id));
  return { server, local, usable: local.filter((k) => active.has(k.keyId)), localError };
}

export function useKeyRing(username: string) {
  return useQuery({ queryKey: keyKeys.ring(username), queryFn: () => loadKeyRing(username) });
}

export function keysChanged(client: QueryClient): Promise<void> {
  return client.invalidateQueries({ queryKey: keyKeys.all });
}

async function revokeOnServer(keyId: string, password: string, reason: string): Promise<void> {
  unwrap(await api.POST("/api/keys/{key_id}/revoke", { params: { path: { key_id: keyId } }, body: { password, reason } }));
}

export interface RegistrationIn {
  name: string;
  password: string;
  /** Active keys to revoke once the new one is registered (a rotation). */
  rotate: readonly Key[];
}

/** A new key pair made here, its public key registered and its private key kept here; a
 * rotation then revokes the old keys. The ring is asked for again even when a step failed:
 * a key registered before a revocation was refused is still registered. */
export function registerKeyMutation(client: QueryClient, username: string) {
  return {
    mutationFn: async ({ name, password, rotate }: RegistrationIn) => {
      const generated = await generateSigningKey();
      const registered = unwrap(await api.POST("/api/keys", { body: { public_key: generated.publicKey, name, password } }));
      await saveKey(username, generated, name);
      for (const old of rotate) {
        await revokeOnServer(old.key_id, password, `rotated to ${registered.key_id}`);
        await deleteKey(username, old.key_id);
      }
      return registered;
    },
    onSettled: () => keysChanged(client),
  };
}

export function useRegisterKey(username: string) {
  return useMutation(registerKeyMutation(useQueryClient(), username));
}

/** Revoke one of my keys on the server and forget its private key here. */
export function revokeKeyMutation(client: QueryClient, username: string) {
  return {
    mutationFn: async ({ keyId, password, reason }: { keyId: string; password: string; reason: string }) => {
      await revokeOnServer(keyId, password, reason);
      await deleteKey(username, keyId);
    },
    onSuccess: () => keysChanged(client),
  };
}

export function useRevokeKey(username: string) {
  return useMutation(revokeKeyMutation(useQueryClient(), username));
}
