/** The side column beside the canvas: the minimap, the inspector of the selected goal or
 * terminal, and the findings. */
import type { RefObject } from "react";

import type { Finding } from "../api/client";
import { SideMinimap } from "./canvas";
import { FindingsPanel } from "./FindingsPanel";
import { goals, terminals } from "./graph";
import { GoalRows } from "./GoalRows";
import { GoalInspector } from "./Inspector";
import { useEditor } from "./store";
import { TerminalInspector } from "./TerminalInspector";
import type { EditorActions } from "./useEditorActions";
import type { Editing } from "./useEditing";
import type { FlowElements } from "./useFlowElements";

interface SideProps {
  editing: Editing;
  actions: EditorActions;
  elements: FlowElements;
  titleRef: RefObject<HTMLInputElement | null>;
  width: number;
  frameHeight: number;
}

export function EditorSide({ editing, actions, elements, titleRef, width, frameHeight }: SideProps) {
  return (
    <aside className="editor-side" aria-label="Inspector and findings">
      <SideMinimap width={width - 8} height={Math.round(Math.min(140, Math.max(80, frameHeight * 0.16)))} />
      <section className="editor-inspector" aria-labelledby="editor-inspector-title" tabIndex={0} data-testid="editor-inspector">
        <h3 id="editor-inspector-title">Inspector</h3>
        <SelectionInspector editing={editing} actions={actions} markers={elements.markers} local={elements.local} titleRef={titleRef} />
      </section>
      <FindingsPanel findings={elements.findings} onPick={actions.pickFinding} />
    </aside>
  );
}

type SelectionProps = Pick<SideProps, "editing" | "actions" | "titleRef"> & { markers: FlowElements["markers"]; local: Finding[] };

function SelectionInspector({ editing, actions, markers, local, titleRef }: SelectionProps) {
  const selected = useEditor((s) => s.nodes.filter((n) => n.selected).map((n) => n.id).join("\n"));
  const scopePath = useEditor((s) => s.scope.path);
  const { orders, refinement } = editing.view;
  const selectedId = selected && !selected.includes("\n") ? selected : undefined;
  const goal = goals(orders).find((g) => g.id === selectedId);
  const terminal = terminals(orders).find((t) => t.id === selectedId);
  if (goal) {
    return (
      <>
        <GoalRows goal={goal} editOrders={editing.editOrders} actions={actions} />
        <GoalInspector key={goal.id} goal={goal} orders={orders} editOrders={editing.editOrders} titleRef={titleRef} markers={markers} findings={local} />
      </>
    );
  }
  if (terminal) {
    const returnsOf = refinement ? (scopePath[scopePath.length - 1] ?? null) : null;
    return <TerminalInspector key={terminal.id} terminal={terminal} editOrders={editing.editOrders} returnsOf={returnsOf} />;
  }
  return (
    <p className="hint">
      Select one goal or terminal to edit it. Drag from a goal's s (succeed, green), f (fail, orange) or c (violate, red) handle to the
      next goal or terminal.
    </p>
  );
}
