/**
 * The ethical mission execution trace of one path, worded as seed 000 Figure 6 prints it
 * (DESIGN.md, Traces) — the same text as `countersign paths --format trace`.
 */

export type Outcome = "succeed" | "fail" | "violate";

export interface PathLike {
  index: number;
  goals: string[];
  outcomes: string[];
  terminal: string;
}

export interface OrdersLike {
  goals?: { id: string; title?: string | null }[];
  terminals?: { id: string; kind: string }[] | null;
}

const QUESTION = "Did goal Succeed (s), Fail (f), or end with a Constraint (c)?";
const ANSWER: Record<string, string> = { succeed: "succeed", fail: "fail", violate: "constraint" };
const END_LINE: Record<string, string> = {
  complete: "Mission Complete!",
  abort: "Mission Abort!",
};
const DEFAULT_KINDS: Record<string, string> = { COMPLETE: "complete", ABORT: "abort" };

export function traceText(path: PathLike, orders: OrdersLike): string {
  const titles = new Map((orders.goals ?? []).map((g) => [g.id, g.title || g.id]));
  const kinds = new Map(Object.entries(DEFAULT_KINDS));
  for (const t of orders.terminals ?? []) kinds.set(t.id, t.kind);
  const lines = [`Ethical Mission Execution Trace #${path.index}:`, "?- execute_mission."];
  path.goals.forEach((goal, i) => {
    const title = (titles.get(goal) ?? goal).replace(/\.+$/, "");
    lines.push(`Commence: ${title}.`);
    const outcome = path.outcomes[i] ?? "";
    lines.push(`${QUESTION} ${ANSWER[outcome] ?? outcome}.`);
  });
  const kind = kinds.get(path.terminal);
  lines.push((kind && END_LINE[kind]) || `Mission ends at ${path.terminal}.`);
  return lines.join("\n");
}

/** `s f c` shorthand of a path's outcomes, for compact lists. */
export function outcomeLetters(outcomes: string[]): string {
  const letter: Record<string, string> = { succeed: "s", fail: "f", violate: "c" };
  return outcomes.map((o) => letter[o] ?? "?").join(" ");
}
