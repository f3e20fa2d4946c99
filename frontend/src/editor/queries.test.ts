import { describe, expect, it } from "vitest";

import type { MissionDetail, Report } from "../api/client";
import { draftSaved, missionKeys } from "../api/missions";
import { makeQueryClient } from "../api/query";
import { editorKeys, seedOpening } from "./queries";

const mission = { id: "m1", revision: 3, draft_digest: "d3" } as unknown as MissionDetail;

describe("the editor's queries", () => {
  it("a saved draft is cached as answered and invalidates the mission list and the mission's queries", async () => {
    const client = makeQueryClient();
    const list = missionKeys.list({ limit: 20 });
    client.setQueryData(list, { items: [] });
    client.setQueryData(editorKeys.plain("m1"), "old plain orders");
    client.setQueryData(editorKeys.report("m1"), { digest: "d2" });
    const saved = { ...mission, revision: 4 } as MissionDetail;
    await draftSaved(client, saved);
    expect(client.getQueryState(list)?.isInvalidated).toBe(true);
    expect(client.getQueryState(editorKeys.plain("m1"))?.isInvalidated).toBe(true);
    expect(client.getQueryState(editorKeys.report("m1"))?.isInvalidated).toBe(true);
    expect(client.getQueryData(editorKeys.mission("m1"))).toEqual(saved);
  });

  it("opens with the page's report only if it is of the opened draft", async () => {
    const client = makeQueryClient();
    const other = { report: { digest: "d2" } as Report, done: Promise.resolve({ digest: "d2" } as Report) };
    expect(await seedOpening(client, mission, other)).toBeNull();
    expect(client.getQueryData(editorKeys.report("m1"))).toBeUndefined();
    const same = { report: { digest: "d3" } as Report, done: Promise.resolve({ digest: "d3" } as Report) };
    expect(seedOpening(client, mission, same)).toBeNull();
    expect(client.getQueryData(editorKeys.report("m1"))).toEqual({ digest: "d3" });
  });
});
