/**
 * Path rows as aligned cells: step k of every path sits in column k, each cell the goal's id,
 * title and outcome letter, the terminal in its own column after the longest path shown. The
 * editor's path explorer and the review's path list draw their rows from these.
 */
import type { PathLike } from "./trace";

export const OUTCOME_LETTERS: Record<string, string> = { succeed: "s", fail: "f", violate: "c" };
export const OUTCOME_WORDS: Record<string, string> = { succeed: "succeeds", fail: "fails", violate: "constraint violated" };

export interface PathStep {
  goal: string;
  title: string;
  outcome: string;
  letter: string;
}

type Titled = { id: string; title?: string | null; refines?: unknown };
type Titles = { goals?: Titled[] | null; terminals?: Titled[] | null };

/** Titles of the goals and terminals by id (empty when untitled), with the goals inside
 * refinements under their full ids (`G1/G1.1`). */
export function titlesOf(orders: Titles, prefix = "", titles = new Map<string, string>()): Map<string, string> {
  for (const n of [...(orders.goals ?? []), ...(orders.terminals ?? [])]) titles.set(`${prefix}${n.id}`, n.title ?? "");
  for (const g of orders.goals ?? []) {
    if (g.refines && typeof g.refines === "object") titlesOf(g.refines as Titles, `${prefix}${g.id}/`, titles);
  }
  return titles;
}

/** A step's title: a copy of a goal in a bounded refinement's unrolling (`G1/G1.2#3`,
 * `G1/G1.2@600s`) has the title of the goal it copies. */
function titleOf(titles: ReadonlyMap<string, string>, goal: string): string {
  return titles.get(goal) ?? titles.get(goal.replace(/[#@][^/]*/g, "")) ?? "";
}

export function pathSteps(path: PathLike, titles: ReadonlyMap<string, string>): PathStep[] {
  return path.goals.map((goal, i) => {
    const outcome = path.outcomes[i] ?? "";
    return { goal, title: titleOf(titles, goal), outcome, letter: OUTCOME_LETTERS[outcome] ?? "?" };
  });
}

/** The row's text for screen readers: "Path 3: G1 Survey, succeeds; G2 Sample, fails; then ABORT Abort." */
export function pathSentence(path: PathLike, titles: ReadonlyMap<string, string>): string {
  const steps = pathSteps(path, titles).map((s) => `${s.goal}${s.title ? ` ${s.title}` : ""}, ${OUTCOME_WORDS[s.outcome] ?? s.outcome}`);
  const end = titles.get(path.terminal);
  return `Path ${path.index}: ${steps.join("; ")}; then ${path.terminal}${end ? ` ${end}` : ""}.`;
}

/** Column widths in px: the index, one per step, the terminal. */
export const COLUMN = { index: 64, step: 168, terminal: 184 };

/** The CSS grid columns for paths of up to `steps` goals (every row uses the same, so they align). */
export function gridColumns(steps: number): string {
  return `${COLUMN.index}px repeat(${Math.max(1, steps)}, ${COLUMN.step}px) ${COLUMN.terminal}px`;
}

export function gridWidth(steps: number): number {
  return COLUMN.index + Math.max(1, steps) * COLUMN.step + COLUMN.terminal;
}
