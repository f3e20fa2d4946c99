import { BaseEdge, type EdgeProps, getBezierPath, Handle, type Node, type NodeProps, Position } from "@xyflow/react";
import { memo } from "react";

import { OUTCOME_LABEL, OUTCOME_LETTER, OUTCOMES } from "./graph";

export interface NodeData extends Record<string, unknown> {
  label: string;
  start: boolean;
  codes: string[];
  severity: "error" | "warning" | null;
  terminalKind?: "complete" | "abort";
  /** A goal carried out by its refinement. */
  refined?: boolean;
  /** The meeting a team's rendezvous goal names. */
  meet?: string | null;
  /** The parent's outcome a refinement terminal returns ("nothing" when it names none). */
  returns?: string | null;
}
export type GoalNodeType = Node<NodeData, "goal">;
export type TerminalNodeType = Node<NodeData, "terminal">;

function Markers({ id, data }: { id: string; data: NodeData }) {
  if (data.codes.length === 0) return null;
  return (
    <span
      className={`node-markers ${data.severity === "error" ? "bad" : "warn"}`}
      data-testid={`markers-${id}`}
      title={`Findings: ${data.codes.join(", ")}`}
    >
      {data.severity === "error" ? "✖ " : "⚠ "}
      {data.codes.join(" ")}
    </span>
  );
}

/** An id with break opportunities where a word meets a number or a separator ("PSMD" "14.0"), so
 * that far out, drawn large, a long id wraps inside its node instead of running into the next. */
function BreakableId({ id }: { id: string }) {
  const parts = id.split(/(?<=[A-Za-z])(?=\d)|(?=[._/-])/);
  return (
    <div className="node-id">
      {parts.map((part, i) => (
        <span key={i}>
          {i > 0 && <wbr />}
          {part}
        </span>
      ))}
    </div>
  );
}

export const GoalNode = memo(function GoalNode({ id, data, selected }: NodeProps<GoalNodeType>) {
  return (
    <div
      className={`graph-node goal-node${selected ? " selected" : ""}${data.severity ? ` marked-${data.severity}` : ""}`}
      data-testid={`node-${id}`}
    >
      {/* Handles carry a title, not an aria-label: a div without a role may not have one
          (axe: aria-prohibited-attr); the node's own label names the goal and its findings. */}
      <Handle type="target" position={Position.Left} id="in" className="handle handle-in" data-testid={`handle-${id}-in`} title={`Into ${id}`} />
      <BreakableId id={id} />
      <div className="node-head">
        <code>{id}</code>
        {data.start && <span className="node-start">start</span>}
        <Markers id={id} data={data} />
      </div>
      <div className="node-title">{data.label}</div>
      {(data.refined || data.meet) && (
        <div className="node-tags">
          {data.refined && (
            <span className="node-tag node-refined" data-testid={`refined-${id}`}>
              refined ▸
            </span>
          )}
          {data.meet && (
            <span className="node-tag node-meet" data-testid={`meet-${id}`}>
              meet {data.meet}
            </span>
          )}
        </div>
      )}
      {OUTCOMES.map((o, i) => (
        <Handle
          key={o}
          type="source"
          position={Position.Right}
          id={o}
          className={`handle handle-${o}`}
          style={{ top: `${25 + i * 25}%` }}
          data-testid={`handle-${id}-${o}`}
          title={`${id} ${OUTCOME_LABEL[o]}: drag to the next goal or terminal`}
        >
          {OUTCOME_LETTER[o]}
        </Handle>
      ))}
    </div>
  );
});

export const TerminalNode = memo(function TerminalNode({ id, data, selected }: NodeProps<TerminalNodeType>) {
  return (
    <div
      className={`graph-node terminal-node terminal-${data.terminalKind ?? "complete"}${selected ? " selected" : ""}${data.severity ? ` marked-${data.severity}` : ""}`}
      data-testid={`node-${id}`}
    >
      <Handle type="target" position={Position.Left} id="in" className="handle handle-in" data-testid={`handle-${id}-in`} title={`Into ${id}`} />
      <BreakableId id={id} />
      <div className="node-head">
        <code>{id}</code>
        {data.returns ? (
          <span className="node-kind node-returns" data-testid={`returns-${id}`}>
            returns {data.returns}
          </span>
        ) : (
          <span className="node-kind">{data.terminalKind === "abort" ? "abort" : "complete"}</span>
        )}
        <Markers id={id} data={data} />
      </div>
      <div className="node-title">{data.label}</div>
    </div>
  );
});

export const NODE_TYPES = { goal: GoalNode, terminal: TerminalNode };

/**
 * An outcome edge: a bezier path with its label (the outcome letter, plus finding codes) drawn
 * as plain SVG text. React Flow's own labels measure their text (getBBox) on every render,
 * which dominated opening large missions; this one needs no measurement.
 */
export const OutcomeEdge = memo(function OutcomeEdge({
  id,
  sourceX,
  sourceY,
  targetX,
  targetY,
  sourcePosition,
  targetPosition,
  style,
  markerEnd,
  label,
  labelStyle,
  data,
}: EdgeProps) {
  const [path, labelX, labelY] = getBezierPath({ sourceX, sourceY, targetX, targetY, sourcePosition, targetPosition });
  return (
    <>
      {data?.loop ? <path d={path} className="loop-halo" strokeWidth={16} /> : null}
      <BaseEdge id={id} path={path} style={style} markerEnd={markerEnd} />
      {label ? (
        <text x={labelX} y={labelY} dy="0.3em" textAnchor="middle" className="outcome-edge-label" style={labelStyle}>
          {label}
        </text>
      ) : null}
    </>
  );
});

export const EDGE_TYPES = { outcome: OutcomeEdge };
