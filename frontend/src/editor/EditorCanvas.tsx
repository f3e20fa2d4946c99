/** The graph canvas (React Flow): the nodes and edges in the store, wiring, dragging, the
 * scope pick of a constraint, a double-click that opens a refinement, and the keys. */
import { Background, Controls, ReactFlow } from "@xyflow/react";
import type { RefObject } from "react";

import { FIT, MIN_ZOOM, ZoomDetail } from "./canvas";
import { goals } from "./graph";
import { useScopePickClick } from "./Inspector";
import { EDGE_TYPES, NODE_TYPES } from "./nodes";
import { useEditor } from "./store";
import { useCanvasKeys } from "./useCanvasKeys";
import { useConnections } from "./useConnections";
import type { EditorActions } from "./useEditorActions";
import type { Editing } from "./useEditing";
import { LARGE_GOALS } from "./useFlowElements";

export function EditorCanvas({ editing, actions, large, canvasRef }: { editing: Editing; actions: EditorActions; large: boolean; canvasRef: RefObject<HTMLDivElement | null> }) {
  const nodes = useEditor((s) => s.nodes);
  const edges = useEditor((s) => s.edges);
  const ready = useEditor((s) => s.ready);
  const onNodesChange = useEditor((s) => s.onNodesChange);
  const onEdgesChange = useEditor((s) => s.onEdgesChange);
  const connections = useConnections(editing, canvasRef);
  const onScopePickClick = useScopePickClick(editing.editPanelOrders);
  const onCanvasKey = useCanvasKeys(actions);
  const { latestScoped, view } = editing;
  return (
    <div
      ref={canvasRef}
      className="editor-canvas"
      tabIndex={0}
      role="group"
      aria-label="Mission graph (Tab moves between nodes; press ? for the keyboard shortcuts)"
      onKeyDown={onCanvasKey}
      data-testid="editor-canvas"
      data-ready={ready ? "true" : "false"}
    >
      <ReactFlow
        nodes={nodes}
        edges={edges}
        nodeTypes={NODE_TYPES}
        edgeTypes={EDGE_TYPES}
        onNodesChange={onNodesChange}
        onEdgesChange={onEdgesChange}
        {...connections}
        // A constraint's scope names the goals of the mission (or member), not of a refinement.
        onNodeClick={view.refinement ? undefined : onScopePickClick}
        onNodeDoubleClick={(_e, node) => {
          if (goals(latestScoped().orders).find((g) => g.id === node.id)?.refines) actions.openRefinement(node.id);
        }}
        deleteKeyCode={null}
        edgesFocusable={false}
        minZoom={MIN_ZOOM}
        fitView={!large}
        fitViewOptions={FIT}
        onlyRenderVisibleElements={nodes.length > LARGE_GOALS}
        proOptions={{ hideAttribution: true }}
      >
        <Background />
        <Controls showInteractive={false} fitViewOptions={FIT} />
        <ZoomDetail canvas={canvasRef} />
      </ReactFlow>
    </div>
  );
}
