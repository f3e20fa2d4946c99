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

type Titled = { id: string; title?: string | null };

/** Titles of the goals and terminals by id (empty when untitled). */
export function titlesOf(orders: { goals?: Titled[] | null; terminals?: Titled[] | null }): Map<string, string> {
  const titles = new Map<string, string>();
  for (const n of [...(orders.goals ?? []), ...(orders.terminals ?? [])]) titles.set(n.id, n.title ?? "");
  return titles;
}

export function pathSteps(path: PathLike, titles: ReadonlyMap<string, string>): PathStep[] {
  return path.goals.map((goal, i) => {
    const outcome = path.outcomes[i] ?? "";
    return { goal, title: titles.get(goal) ?? "", outcome, letter: OUTCOME_LETTERS[outcome] ?? "?" };
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
