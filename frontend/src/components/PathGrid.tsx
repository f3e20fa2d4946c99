/** One path as a row of aligned cells (pathGrid.ts): index, each goal (id, title, outcome
 * letter), the terminal. Titles are text, never markup; long ones are cut with their full text
 * in the tooltip. */
import type { CSSProperties, HTMLAttributes } from "react";

import { gridColumns, pathSentence, pathSteps } from "../pathGrid";
import type { PathLike } from "../trace";

export function PathGridRow({
  path,
  titles,
  steps,
  style,
  className = "",
  note,
  ...rest
}: {
  path: PathLike;
  /** Shown after the terminal, e.g. the path's probability. */
  note?: string | null;
  titles: ReadonlyMap<string, string>;
  steps: number;
  style?: CSSProperties;
  className?: string;
} & Omit<HTMLAttributes<HTMLDivElement>, "style" | "className">) {
  const cells = pathSteps(path, titles);
  const end = titles.get(path.terminal) ?? "";
  return (
    <div
      {...rest}
      className={`path-grid-row ${className}`}
      style={{ ...style, gridTemplateColumns: gridColumns(steps) }}
      aria-label={pathSentence(path, titles)}
      data-path={path.index}
    >
      <span className="path-cell path-index">#{path.index}</span>
      {cells.map((s, i) => (
        <span key={i} className="path-cell path-step" title={`${s.goal}${s.title ? `: ${s.title}` : ""} (${s.outcome})`} style={{ gridColumn: i + 2 }}>
          <code className="path-goal">{s.goal}</code> <span className="path-title">{s.title}</span>
          <span className={`outcome-letter outcome-${s.outcome}`}>{s.letter}</span>
        </span>
      ))}
      <span className="path-cell path-terminal" style={{ gridColumn: steps + 2 }} title={`${path.terminal}${end ? `: ${end}` : ""}`}>
        → <strong>{path.terminal}</strong> <span className="path-title">{end}</span>
        {note && <span className="hint"> {note}</span>}
      </span>
    </div>
  );
}

/** Column headings matching the rows. */
export function PathGridHead({ steps }: { steps: number }) {
  return (
    <div className="path-grid-row path-grid-head" style={{ gridTemplateColumns: gridColumns(steps) }} aria-hidden="true">
      <span className="path-cell">Path</span>
      {Array.from({ length: steps }, (_, i) => (
        <span key={i} className="path-cell">
          Step {i + 1}
        </span>
      ))}
      <span className="path-cell">Ends at</span>
    </div>
  );
}
