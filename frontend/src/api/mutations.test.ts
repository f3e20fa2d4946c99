/**
 * The mutation hooks' options as TanStack Query runs them (MutationObserver, the hooks' own
 * engine): after a write that succeeded, a watched query of the resource it changed is asked for
 * again; after a refusal, nothing is asked for again. The requests are answered by a stand-in
 * for the typed client's methods; the browser's key store by a stand-in (no IndexedDB here).
 */
import { type MutationOptions, MutationObserver, QueryClient, type QueryKey, QueryObserver } from "@tanstack/react-query";
import { afterEach, describe, expect, it, vi } from "vitest";

import { approvalKeys, decideMutation, revokeMutation } from "./approvals";
import { changePasswordMutation } from "./auth";
import { cancelCampaignMutation, campaignKeys, startCampaignMutation } from "./campaigns";
import { api } from "./client";
import { keyKeys, registerKeyMutation, revokeKeyMutation } from "./keys";
import {
  createMissionMutation,
  createVersionMutation,
  deleteMissionMutation,
  importMissionMutation,
  missionKeys,
  saveDraftMutation,
  saveLayoutMutation,
} from "./missions";
import { rehearsalKeys, stopRehearsalMutation } from "./rehearsals";
import { attachRehearsalMutation, submissionKeys, submissionMutation } from "./submissions";
import { createTokenMutation, revokeTokenMutation, tokenKeys } from "./tokens";
import { createUserMutation, updateUserMutation, userKeys } from "./users";
import { saveVehicleMutation, vehicleKeys } from "./vehicles";

vi.mock("../crypto/keystore", () => ({
  generateSigningKey: vi.fn(async () => ({ publicKey: "public" })),
  saveKey: vi.fn(async () => undefined),
  deleteKey: vi.fn(async () => undefined),
  listKeys: vi.fn(async () => []),
}));

afterEach(() => {
  vi.restoreAllMocks();
});

/** Every write the client sends is answered with `status` and `body`. */
function answer(status: number, body: unknown = { id: "m1", revision: 2, key_id: "k2", digest: "r9" }) {
  const json = status === 204 ? null : JSON.stringify(body);
  for (const method of ["POST", "PUT", "PATCH", "DELETE"] as const) {
    vi.spyOn(api, method).mockImplementation(async () => {
      const response = new Response(json, { status, headers: { "Content-Type": "application/json" } });
      return (response.ok ? { data: status === 204 ? undefined : body, response } : { error: body, response }) as never;
    });
  }
}

/** A mounted query of `key`: how many times it has been asked for. */
async function watch(client: QueryClient, key: QueryKey): Promise<() => number> {
  let calls = 0;
  const observer = new QueryObserver(client, { queryKey: key, queryFn: async () => ++calls, retry: false });
  observer.subscribe(() => undefined);
  await vi.waitFor(() => expect(observer.getCurrentResult().status).toBe("success"));
  return () => calls;
}

/** Runs the mutation to its end (onSuccess or onError included); true when it succeeded. */
async function run(options: MutationOptions<unknown, Error, never>, variables: unknown): Promise<boolean> {
  const observer = new MutationObserver(new QueryClient(), options);
  return observer.mutate(variables as never).then(
    () => true,
    () => false,
  );
}

const sign = async () => "envelope";
type Case = [string, (client: QueryClient) => object, unknown, QueryKey, number?];

const CASES: Case[] = [
  ["create a mission", (c) => createMissionMutation(c), { id: "m1" }, missionKeys.list({ limit: 25 })],
  ["import a mission", (c) => importMissionMutation(c), { body: "{}", contentType: "application/json" }, missionKeys.list({ limit: 25 })],
  ["save the draft", (c) => saveDraftMutation(c, "m1"), { revision: 1, orders: {} }, missionKeys.list({ limit: 25 })],
  ["create a version", (c) => createVersionMutation(c, "m1"), undefined, missionKeys.detail("m1")],
  ["delete a mission", (c) => deleteMissionMutation(c, "m2"), undefined, missionKeys.list({ limit: 25 }), 204],
  ["start a campaign", (c) => startCampaignMutation(c, "m1"), { version: 1, body: {} }, campaignKeys.ofMission("m1")],
  ["cancel a campaign", (c) => cancelCampaignMutation(c, "m1"), "c1", campaignKeys.ofMission("m1")],
  ["submit a version", (c) => submissionMutation(c, "m1"), { submit: 1 }, submissionKeys.list(25)],
  ["attach a rehearsal record", (c) => attachRehearsalMutation(c, "m1", 7), "r1", submissionKeys.list(25)],
  ["decide", (c) => decideMutation(c, "m1", 7), { decision: "approved", reason: "", keyId: "k", password: "p", sign }, approvalKeys.history({ limit: 25 })],
  ["revoke an approval", (c) => revokeMutation(c, "m1", 3), { reason: "r", keyId: "k", password: "p", sign }, approvalKeys.one(3)],
  ["stop a rehearsal", (c) => stopRehearsalMutation(c, "m1"), "r1", rehearsalKeys.list("m1", 50)],
  ["register a vehicle", (c) => saveVehicleMutation(c), { id: "remus-100" }, vehicleKeys.all],
  ["create an account", (c) => createUserMutation(c), { username: "ann", role: "operator", password: "p" }, userKeys.all],
  ["change an account", (c) => updateUserMutation(c), { user: { id: 1 }, patch: { disabled: true } }, userKeys.all],
  ["create a token", (c) => createTokenMutation(c), { name: "ci", scopes: ["read"] }, tokenKeys.all],
  ["revoke a token", (c) => revokeTokenMutation(c), 4, tokenKeys.all, 204],
  ["change my password", (c) => changePasswordMutation(c), { current_password: "a", new_password: "b" }, tokenKeys.all, 204],
  ["revoke a signing key", (c) => revokeKeyMutation(c, "sup"), { keyId: "k1", password: "p", reason: "lost" }, keyKeys.ring("sup")],
];

describe("a mutation hook", () => {
  it.each(CASES)("%s: a query of what it changed is asked for again", async (_, options, variables, key, status = 200) => {
    answer(status);
    const client = new QueryClient();
    const calls = await watch(client, key);
    const elsewhere = await watch(client, ["elsewhere"]);
    expect(await run(options(client) as never, variables)).toBe(true);
    expect(calls()).toBe(2);
    // Only what the write changed: a query of another resource is left as it was.
    expect(elsewhere()).toBe(1);
    expect(client.getQueryState(["elsewhere"])?.isInvalidated).toBe(false);
  });

  it.each(CASES)("%s, refused: nothing is asked for again", async (_, options, variables, key) => {
    answer(422, { title: "Unprocessable content", detail: "refused" });
    const client = new QueryClient();
    const calls = await watch(client, key);
    expect(await run(options(client) as never, variables)).toBe(false);
    expect(calls()).toBe(1);
    expect(client.getQueryState(key)?.isInvalidated).toBe(false);
  });

  it("surfaces the server's problem document as the error's message", async () => {
    answer(409, { title: "Conflict", detail: "the mission has versions" });
    const observer = new MutationObserver(new QueryClient(), deleteMissionMutation(new QueryClient(), "m1"));
    await expect(observer.mutate()).rejects.toThrow("Conflict: the mission has versions");
  });

  it("a key registration that failed part-way still asks for the key ring (the new key may be registered)", async () => {
    answer(403, { title: "Forbidden" });
    const client = new QueryClient();
    const calls = await watch(client, keyKeys.ring("sup"));
    expect(await run(registerKeyMutation(client, "sup") as never, { name: "n", password: "p", rotate: [] })).toBe(false);
    expect(calls()).toBe(2);
  });

  it("saved positions mark the mission stale, asked for when next opened, not while the editor is open", async () => {
    answer(200, {});
    const client = new QueryClient();
    const calls = await watch(client, missionKeys.detail("m1"));
    expect(await run(saveLayoutMutation(client, "m1") as never, { G1: { x: 1, y: 2 } })).toBe(true);
    expect(client.getQueryState(missionKeys.detail("m1"))?.isInvalidated).toBe(true);
    expect(calls()).toBe(1);
  });
});
