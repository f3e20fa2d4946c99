/**
 * The graph editor of a mission draft (operators), composed of hooks and panels: the pure logic
 * lives in graph.ts, history.ts and layout.ts; the state in one store (store.ts) with named
 * actions; the edits, checks and saves in useEditing (every edit sends the new orders to
 * /api/validate at once, from the event handler, then saves the draft with If-Match; typing
 * waits for a pause first); the server state read through TanStack Query (queries.ts); the
 * actions in useEditorActions; each part of the screen in its own panel.
 */
import "@xyflow/react/dist/style.css";
import "./editor.css";

import { useQueryClient } from "@tanstack/react-query";
import { ReactFlowProvider } from "@xyflow/react";
import { useRef, useState } from "react";

import type { MissionDetail, Report } from "../api/client";
import { type ReportPrefetch, reportOf } from "../api/reportPrefetch";
import { Splitter, useEditorFrame, useSideWidth } from "./canvas";
import { ConflictDialog } from "./ConflictDialog";
import { EditorCanvas } from "./EditorCanvas";
import { EditorMessages } from "./EditorMessages";
import { EditorSide } from "./EditorSide";
import { EditorToolbar } from "./EditorToolbar";
import { LowerPanels } from "./LowerPanels";
import { PlanDialog } from "./PlanDialog";
import { seedOpening } from "./queries";
import { ScopeBar } from "./ScopeBar";
import { teamOf } from "./scope";
import { ShortcutsDialog } from "./Shortcuts";
import { createEditorStore, EditorStoreContext, useEditor } from "./store";
import { useEditorActions } from "./useEditorActions";
import { useFlowElements } from "./useFlowElements";

/** Saves update the query cache (api/missions.ts), so the page shows them without re-reading.
 * `report`: the saved draft's report if the page asked for it beside the mission; it is used only
 * if it is of this draft (its digest), else the editor asks for it. */
export default function MissionEditor(props: { mission: MissionDetail; report?: ReportPrefetch | null }) {
  const { mission, report } = props;
  const client = useQueryClient();
  const [store] = useState(() => createEditorStore(mission, reportOf(report, mission.draft_digest)));
  const [opening] = useState(() => seedOpening(client, mission, report));
  return (
    <EditorStoreContext.Provider value={store}>
      <ReactFlowProvider>
        <Editor mission={mission} opening={opening} />
      </ReactFlowProvider>
    </EditorStoreContext.Provider>
  );
}

function Editor({ mission, opening }: { mission: MissionDetail; opening: Promise<Report | null> | null }) {
  const titleRef = useRef<HTMLInputElement>(null);
  const { editing, open, actions } = useEditorActions(mission, opening, titleRef);
  const elements = useFlowElements(open.large);
  const editorRef = useRef<HTMLDivElement>(null);
  const mainRef = useRef<HTMLDivElement>(null);
  const canvasRef = useRef<HTMLDivElement>(null);
  // The scope bar (team members, breadcrumbs) shows above the canvas for teams and refinements.
  const scopeBar = useEditor((s) => teamOf(s.history.present.orders) !== null || s.scope.path.length > 0);
  const frameHeight = useEditorFrame(editorRef, mainRef, scopeBar);
  const [sideWidth, setSideWidth] = useSideWidth();
  const conflict = useEditor((s) => s.conflict);
  const { reloadTheirs, resolve } = editing.autosave;
  const { dialogs } = actions;
  return (
    <div className="editor" ref={editorRef}>
      <EditorToolbar missionId={mission.id} actions={actions} />
      <EditorMessages />
      <ScopeBar openScope={actions.openScope} />
      <div className="editor-main" ref={mainRef} style={{ height: frameHeight, gridTemplateColumns: `minmax(0, 1fr) 8px ${sideWidth}px` }}>
        <EditorCanvas editing={editing} actions={actions} large={open.large} canvasRef={canvasRef} />
        <Splitter width={sideWidth} onWidth={setSideWidth} />
        <EditorSide editing={editing} actions={actions} elements={elements} titleRef={titleRef} width={sideWidth} frameHeight={frameHeight} />
      </div>
      <LowerPanels missionId={mission.id} editing={editing} actions={actions} elements={elements} />
      {dialogs.plan && <PlanDialog mission={mission} orders={editing.panelOrders} onClose={() => dialogs.showPlan(false)} />}
      {dialogs.shortcuts && <ShortcutsDialog onClose={() => dialogs.showShortcuts(false)} />}
      {conflict && <ConflictDialog conflict={conflict} onReload={reloadTheirs} onResolve={resolve} />}
    </div>
  );
}
