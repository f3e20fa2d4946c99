/**
 * One row of the review's path list: the path number, the terminal and the
 * probability first, so that they stay in view however long the path is (the three cells stick
 * to the left edge when the list scrolls sideways), then each step as its goal id and outcome
 * letter. Titles are not printed in the cells, where they made every row look alike ("G1
 * Transit to patrol ..."): they are in each cell's tooltip and in the row's sentence for screen
 * readers. Text only, never markup.
 */
import type { CSSProperties } from "react";

import { OUTCOME_WORDS, pathSentence, pathSteps } from "../../pathGrid";
import type { PathLike } from "../../trace";
import "./review.css";

/** Column widths in px: number, terminal, probability; steps are sized by `stepWidth`. */
export const LEAD = { index: 64, terminal: 132, chance: 96 };

/** Wide enough for the longest goal id shown and its letter, within reason (longer ids are cut
 * with an ellipsis, their full text in the tooltip). */
export function stepWidth(longestId: number): number {
  return Math.min(168, Math.max(60, 32 + 9 * longestId));
}

export function rowColumns(steps: number, step: number): string {
  return `${LEAD.index}px ${LEAD.terminal}px ${LEAD.chance}px repeat(${Math.max(1, steps)}, ${step}px)`;
}

export function rowWidth(steps: number, step: number): number {
  return LEAD.index + LEAD.terminal + LEAD.chance + Math.max(1, steps) * step;
}

export function ReviewPathHead({ steps, step }: { steps: number; step: number }) {
  return (
    <div
      className="review-path-row review-path-head"
      style={{ gridTemplateColumns: rowColumns(steps, step), width: rowWidth(steps, step) }}
      aria-hidden="true"
    >
      <span className="rp-cell rp-lead rp-index">Path</span>
      <span className="rp-cell rp-lead rp-terminal">Ends at</span>
      <span className="rp-cell rp-lead rp-chance">Probability</span>
      {Array.from({ length: steps }, (_, i) => (
        <span key={i} className="rp-cell rp-step">
          Step {i + 1}
        </span>
      ))}
    </div>
  );
}

export function ReviewPathRow({
  path,
  titles,
  steps,
  step,
  chance,
  style,
}: {
  path: PathLike;
  titles: ReadonlyMap<string, string>;
  steps: number;
  step: number;
  chance: string | null;
  style: CSSProperties;
}) {
  const end = titles.get(path.terminal) ?? "";
  return (
    <div
      role="listitem"
      className="review-path-row"
      style={{ ...style, gridTemplateColumns: rowColumns(steps, step), width: rowWidth(steps, step) }}
      aria-label={pathSentence(path, titles) + (chance ? ` Probability ${chance}.` : "")}
      data-path={path.index}
      data-testid="review-path-row"
    >
      <span className="rp-cell rp-lead rp-index">#{path.index}</span>
      <span className="rp-cell rp-lead rp-terminal" title={`${path.terminal}${end ? `: ${end}` : ""}`} data-testid="review-path-terminal">
        <strong>{path.terminal}</strong>
      </span>
      <span className="rp-cell rp-lead rp-chance" data-testid="review-path-chance">
        {chance ?? "—"}
      </span>
      {pathSteps(path, titles).map((s, i) => (
        <span
          key={i}
          className="rp-cell rp-step"
          title={`${s.goal}${s.title ? `: ${s.title}` : ""} — ${OUTCOME_WORDS[s.outcome] ?? s.outcome}`}
          data-testid="review-path-step"
        >
          <code className="rp-goal">{s.goal}</code>
          <span className={`outcome-letter outcome-${s.outcome}`}>{s.letter}</span>
        </span>
      ))}
    </div>
  );
}
