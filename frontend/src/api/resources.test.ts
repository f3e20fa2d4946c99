/** What each write invalidates, resource by resource, and that a refusal is not asked again. */
import { QueryClient, QueryObserver } from "@tanstack/react-query";
import { describe, expect, it } from "vitest";

import { approvalKeys, decisionRecorded, recordRevoked } from "./approvals";
import { attachCampaignMutation, campaignKeys, campaignsChanged } from "./campaigns";
import { ApiError, type MissionDetail } from "./client";
import { missionChanged, missionKeys, missionSaved } from "./missions";
import { makeQueryClient } from "./query";
import { rehearsalKeys, rehearsalStored, type StoredRecord } from "./rehearsals";
import { reportKeys } from "./reports";
import { attachRehearsalMutation, submissionKeys, submissionMutation } from "./submissions";
import { vehicleKeys } from "./vehicles";
import { versionKeys } from "./versions";

const KEYS = {
  list: missionKeys.list({ limit: 25 }),
  m1: missionKeys.detail("m1"),
  m2: missionKeys.detail("m2"),
  m1Standing: missionKeys.standing("m1", "draft"),
  m1Review: versionKeys.review("m1", 1),
  m2Review: versionKeys.review("m2", 1),
  m1Records: rehearsalKeys.list("m1", null),
  m1Records50: rehearsalKeys.list("m1", 50),
  m1Campaigns: campaignKeys.ofMission("m1"),
  attached7: campaignKeys.attached(7),
  cited7: campaignKeys.cited(7),
  submissions: submissionKeys.list(25),
  history: approvalKeys.history({ limit: 25 }),
  record3: approvalKeys.one(3),
  executions3: approvalKeys.executions(3),
  report1: reportKeys.draft("m1", "d1"),
  report2: reportKeys.draft("m2", "d2"),
  vehicles: vehicleKeys.all,
  rehearsal: rehearsalKeys.record("r1"),
} as const;
type Name = keyof typeof KEYS;

function seeded(): QueryClient {
  const client = new QueryClient();
  for (const key of Object.values(KEYS)) client.setQueryData(key, [{ seeded: true }]);
  return client;
}

/** The names of the seeded queries a write marked stale. */
function stale(client: QueryClient): Name[] {
  const invalid = new Set(
    client
      .getQueryCache()
      .getAll()
      .filter((q) => q.state.isInvalidated)
      .map((q) => q.queryHash),
  );
  return (Object.keys(KEYS) as Name[]).filter((name) => invalid.has(JSON.stringify(KEYS[name]))).sort();
}

const MISSION_M1: Name[] = ["m1", "m1Standing", "m1Review", "m1Records", "m1Records50", "m1Campaigns"];
const SUBMISSION: Name[] = [...MISSION_M1, "list", "submissions", "attached7", "cited7"];

describe("what a write invalidates", () => {
  it.each([
    ["submit or withdraw", (c: QueryClient) => submissionMutation(c, "m1").onSuccess()],
    ["attach a rehearsal record", (c: QueryClient) => attachRehearsalMutation(c, "m1", 7).onSuccess()],
    ["attach a campaign", (c: QueryClient) => attachCampaignMutation(c, "m1", 7).onSuccess()],
  ])("%s: the submissions and that mission, not another mission, the records or reports", async (_, write) => {
    const client = seeded();
    await write(client);
    expect(stale(client)).toEqual([...SUBMISSION].sort());
  });

  it.each([
    ["a decision", decisionRecorded],
    ["a revocation", recordRevoked],
  ])("%s: the submissions, the mission and the signed records", async (_, write) => {
    const client = seeded();
    await write(client, "m1");
    expect(stale(client)).toEqual([...SUBMISSION, "history", "record3", "executions3"].sort());
  });

  it("a campaign started or stopped: that mission's campaigns", async () => {
    const client = seeded();
    await campaignsChanged(client, "m1");
    expect(stale(client)).toEqual(["m1Campaigns"]);
  });

  it("a saved draft or a new version: the whole mission, the lists and its reports", async () => {
    const client = seeded();
    await missionChanged(client, "m1");
    expect(stale(client)).toEqual([...MISSION_M1, "list", "report1"].sort());
  });

  it("the editor's save: the mission as answered, shown with no request; the lists marked stale", async () => {
    const client = seeded();
    const saved = { id: "m1", revision: 2 } as unknown as MissionDetail;
    await missionSaved(client, saved);
    expect(client.getQueryData(KEYS.m1)).toEqual(saved);
    expect(stale(client)).toEqual(["list"]);
  });

  it("a stored rehearsal: listed first at once; the shorter lists asked again", async () => {
    const client = seeded();
    const stored = { digest: "r9" } as unknown as StoredRecord;
    await rehearsalStored(client, "m1", stored);
    expect(client.getQueryData<StoredRecord[]>(KEYS.m1Records)?.[0]).toEqual(stored);
    expect(stale(client)).toEqual(["m1Records50"]);
  });
});

describe("the app's query client", () => {
  /** How many times a query failing with `error` is asked (retries at once, for the test). */
  async function attempts(error: unknown): Promise<number> {
    const client = makeQueryClient();
    let calls = 0;
    const observer = new QueryObserver(client, {
      queryKey: ["attempts"],
      retryDelay: 0,
      queryFn: () => {
        calls += 1;
        return Promise.reject(error);
      },
    });
    await new Promise<void>((done) => {
      const stop = observer.subscribe((result) => {
        if (result.status === "error") {
          stop();
          done();
        }
      });
    });
    return calls;
  }

  it("does not ask again after a refusal (4xx), once after a server error", async () => {
    expect(await attempts(new ApiError(404, null))).toBe(1);
    expect(await attempts(new ApiError(409, null))).toBe(1);
    expect(await attempts(new ApiError(503, null))).toBe(2);
  });
});
