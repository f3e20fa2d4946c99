import { QueryClient } from "@tanstack/react-query";
import { describe, expect, it } from "vitest";

import { approvalKeys, approvalsChanged } from "./approvals";
import { ApiError } from "./client";
import { missionKeys, missionsChanged } from "./missions";
import { retryRequest } from "./query";
import { tokenKeys, tokensChanged } from "./tokens";
import { userKeys, usersChanged } from "./users";
import { vehicleKeys, vehicleSaved } from "./vehicles";

function seeded(): QueryClient {
  const client = new QueryClient();
  for (const key of [
    missionKeys.list({ limit: 25 }),
    userKeys.all,
    tokenKeys.all,
    vehicleKeys.all,
    vehicleKeys.versions("remus-100"),
    approvalKeys.history({ limit: 25 }),
  ]) {
    client.setQueryData(key, { seeded: true });
  }
  return client;
}

const stale = (client: QueryClient) =>
  client
    .getQueryCache()
    .getAll()
    .filter((q) => q.state.isInvalidated)
    .map((q) => JSON.stringify(q.queryKey))
    .sort();

describe("what a write invalidates", () => {
  it("a saved vehicle: the registry, its versions and the mission list (drafts are checked again)", async () => {
    const client = seeded();
    await vehicleSaved(client);
    expect(stale(client)).toEqual(
      [missionKeys.list({ limit: 25 }), vehicleKeys.all, vehicleKeys.versions("remus-100")]
        .map((k) => JSON.stringify(k))
        .sort(),
    );
  });

  it("each resource's change invalidates that resource only", async () => {
    for (const [change, key] of [
      [usersChanged, userKeys.all],
      [tokensChanged, tokenKeys.all],
      [missionsChanged, missionKeys.list({ limit: 25 })],
      [approvalsChanged, approvalKeys.history({ limit: 25 })],
    ] as const) {
      const client = seeded();
      await change(client);
      expect(stale(client)).toEqual([JSON.stringify(key)]);
    }
  });
});

describe("retries", () => {
  it("a refusal is not asked again, a server error once", () => {
    expect(retryRequest(0, new ApiError(403, null))).toBe(false);
    expect(retryRequest(0, new ApiError(404, null))).toBe(false);
    expect(retryRequest(0, new ApiError(503, null))).toBe(true);
    expect(retryRequest(1, new ApiError(503, null))).toBe(false);
    expect(retryRequest(0, new TypeError("network"))).toBe(true);
  });
});
