/** The audit page's check that the server keeps to one history (crypto/history.ts). */
import { api, unwrap } from "../../api/client";
import { checkHistory, historyStorageKey } from "../../crypto/history";
import { checkpointOrigin, type Check, type Checkpoint } from "../../crypto/verify";

export async function historyCheck(checkpoint: Checkpoint): Promise<Check> {
  const label = "Log extends the checkpoint this browser saw before";
  const key = historyStorageKey(window.location.origin, checkpointOrigin(checkpoint.note));
  const { problem, seen } = await checkHistory(window.localStorage, key, { size: checkpoint.size, root: checkpoint.root }, async (first, second) =>
    unwrap(await api.GET("/api/log/consistency", { params: { query: { first, second } } })),
  );
  if (problem) return { id: "history", label, ok: false, detail: problem };
  return {
    id: "history",
    label,
    ok: true,
    detail: seen ? `consistent with size ${seen.size} seen before; now size ${checkpoint.size} is kept` : `first checkpoint seen (size ${checkpoint.size}); kept for the next visit`,
  };
}
