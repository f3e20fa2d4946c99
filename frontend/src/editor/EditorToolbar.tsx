/** The editor's toolbar: one row at 1280 px, the less frequent actions in menus (details and
 * summary: Tab reaches each summary, Enter or Space opens it, Escape closes it). */
import { useReactFlow } from "@xyflow/react";

import { FIT } from "./canvas";
import { goals } from "./graph";
import { canRedo, canUndo } from "./history";
import { ImportMenu, NewFromExample } from "./ImportMenu";
import { GotoField } from "./GotoField";
import { useEditor } from "./store";
import { ExportMenu, ToolbarMenu } from "./Toolbar";
import type { EditorActions } from "./useEditorActions";
import { useScopedDraft } from "./useScopedDraft";

const SAVE_TEXT = { saved: "Saved", pending: "Saving…", saving: "Saving…", conflict: "Conflict", error: "Not saved" } as const;

export function EditorToolbar({ missionId, actions }: { missionId: string; actions: EditorActions }) {
  const history = useEditor((s) => s.history);
  const saveState = useEditor((s) => s.saveState);
  return (
    <div className="editor-toolbar" role="toolbar" aria-label="Graph editing" data-testid="editor-toolbar">
      <button type="button" onClick={actions.addGoalNode}>
        Add goal
      </button>
      <ToolbarMenu label="Add terminal">
        <button type="button" className="menu-item" onClick={() => actions.addTerminalNode("complete")}>
          Add complete terminal
        </button>
        <button type="button" className="menu-item" onClick={() => actions.addTerminalNode("abort")}>
          Add abort terminal
        </button>
      </ToolbarMenu>
      <EditMenu actions={actions} />
      <button type="button" onClick={actions.doUndo} disabled={!canUndo(history)}>
        Undo
      </button>
      <button type="button" onClick={actions.doRedo} disabled={!canRedo(history)}>
        Redo
      </button>
      <button type="button" onClick={() => void actions.relayout()}>
        Auto layout
      </button>
      <NodeGoto onGo={actions.goTo} />
      <MoreMenu missionId={missionId} actions={actions} saved={saveState === "saved"} />
      <button type="button" onClick={() => actions.dialogs.showShortcuts(true)} aria-haspopup="dialog" data-testid="shortcuts-button" title="Keyboard shortcuts (?)">
        ?<span className="visually-hidden"> Keyboard shortcuts</span>
      </button>
      <span className={`save-state save-${saveState}`} role="status" data-testid="save-state">
        {SAVE_TEXT[saveState]}
      </span>
    </div>
  );
}

function EditMenu({ actions }: { actions: EditorActions }) {
  const nodes = useEditor((s) => s.nodes);
  const edges = useEditor((s) => s.edges);
  const orders = useScopedDraft().orders;
  const selected = nodes.filter((n) => n.selected).map((n) => n.id);
  return (
    <ToolbarMenu label="Edit">
      <button type="button" className="menu-item" onClick={actions.deleteSelected} disabled={selected.length === 0 && !edges.some((e) => e.selected)}>
        Delete selected
      </button>
      <button type="button" className="menu-item" onClick={actions.duplicateSelected} disabled={!selected.some((id) => goals(orders).some((g) => g.id === id))}>
        Duplicate
      </button>
      <button type="button" className="menu-item" onClick={actions.copySelected} disabled={selected.length === 0}>
        Copy
      </button>
      <button type="button" className="menu-item" onClick={actions.pasteSelected}>
        Paste
      </button>
    </ToolbarMenu>
  );
}

/** The "Go to node" field with the ids of the nodes on the canvas. */
function NodeGoto({ onGo }: { onGo: (id: string) => void }) {
  const ids = useEditor((s) => s.nodes.map((n) => n.id).join("\n"));
  return <GotoField ids={ids ? ids.split("\n") : []} onGo={onGo} />;
}

function MoreMenu({ missionId, actions, saved }: { missionId: string; actions: EditorActions; saved: boolean }) {
  const flow = useReactFlow();
  return (
    <ToolbarMenu label="More">
      <button type="button" className="menu-item" onClick={() => void flow.fitView(FIT)}>
        Zoom to fit
      </button>
      <button type="button" className="menu-item" onClick={() => actions.dialogs.showPlan(true)}>
        Plan survey…
      </button>
      <ImportMenu onImport={actions.importFile} busy={actions.importing} />
      <ExportMenu missionId={missionId} saved={saved} />
      <NewFromExample />
    </ToolbarMenu>
  );
}
