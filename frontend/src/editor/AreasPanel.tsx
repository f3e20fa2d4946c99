/** The Areas panel: the list of areas, one area's vertices, features and a plan view of them. */
import { useRef, useState } from "react";

import { numberPair } from "../api/pair";
import type { Column } from "../components/DataTable";
import { EditableTable } from "../components/EditableTable";
import { CommitField } from "./fields";
import { type Orders } from "./graph";
import { addArea, addVertex, areas, type AreaSpec, deleteArea, type LatLon, parseList, parseNumber, removeVertex, renameArea, setVertex, updateArea } from "./model";
import { AreaChart } from "../map/AreaChart";
import { MarkerBadge, type EditOrders, type Markers } from "./panels";

export interface PlanOverlay {
  /** Route through the plan: lat/lon points, labelled. */
  route: { at: LatLon; label: string }[];
  /** Area ids chosen by the plan, in order. */
  chosen: string[];
}

export function AreasPanel({ orders, editOrders, markers }: { orders: Orders; editOrders: EditOrders; markers: Markers }) {
  const list = areas(orders);
  const [selected, setSelected] = useState<string | null>(list[0]?.id ?? null);
  const current = list.find((a) => a.id === selected) ?? null;
  return (
    <section aria-labelledby="areas-title" className="areas-panel">
      <h3 id="areas-title">Areas</h3>
      <AreaChart
        orders={orders}
        selected={current?.id ?? null}
        onSelect={setSelected}
        onMoveVertex={(area, index, at) => editOrders((o) => setVertex(o, area, index, at), `area:${area}:drag:${index}`)}
        onAddVertex={(area, at) => editOrders((o) => addVertex(o, area, at))}
      />
      <div className="area-list" role="group" aria-label="Choose an area">
        {list.map((a) => (
          <button key={a.id} type="button" aria-pressed={a.id === current?.id} onClick={() => setSelected(a.id)}>
            {a.id} <MarkerBadge markers={markers} id={a.id} />
          </button>
        ))}
        <button
          type="button"
          onClick={() => {
            const r = addArea(orders);
            editOrders(() => r.orders);
            setSelected(r.id);
          }}
        >
          Add area
        </button>
      </div>
      {current && <AreaEditor key={current.id} area={current} orders={orders} editOrders={editOrders} onRenamed={setSelected} />}
    </section>
  );
}

// Length: one area's fields, vertices and chart in one fieldset.
function AreaEditor({
  area,
  orders,
  editOrders,
  onRenamed,
}: {
  area: AreaSpec;
  orders: Orders;
  editOrders: EditOrders;
  onRenamed: (id: string) => void;
}) {
  const id = area.id;
  const polygon = area.polygon ?? [];
  return (
    <fieldset className="panel-box">
      <legend>
        Area <code>{id}</code>
      </legend>
      <CommitField
        id="area-id"
        label="Area id"
        value={id}
        onCommit={(text) => {
          const r = renameArea(orders, id, text.trim());
          if (r.error) return r.error;
          editOrders(() => r.orders);
          onRenamed(text.trim());
        }}
      />
      <label htmlFor="area-title">Area title</label>
      <input id="area-title" value={area.title ?? ""} onChange={(e) => editOrders((o) => updateArea(o, id, { title: e.target.value }), `area:${id}:title`)} />
      <CommitField
        id="area-contexts"
        label="Context tags (comma-separated)"
        value={(area.contexts ?? []).join(", ")}
        onCommit={(text) => editOrders((o) => updateArea(o, id, { contexts: parseList(text) }))}
      />
      <EditableTable
        caption={`Vertices of ${id} (latitude, longitude in degrees)`}
        showCaption
        className="vertices"
        columns={vertexColumns(id, editOrders)}
        rows={polygon.map(numberPair)}
        rowKey={(_, i) => i}
        remove={{
          header: "Remove",
          text: () => "✕",
          label: (_, i) => `Remove vertex ${i + 1}`,
          className: "small",
          onRemove: (_, i) => editOrders((o) => removeVertex(o, id, i)),
        }}
      />
      <button type="button" onClick={() => editOrders((o) => addVertex(o, id))}>
        Add vertex
      </button>{" "}
      <button type="button" className="danger" onClick={() => editOrders((o) => deleteArea(o, id))}>
        Delete area {id}
      </button>
    </fieldset>
  );
}

/** A vertex a row: its number, latitude and longitude (typing is grouped per field). */
function vertexColumns(id: string, editOrders: EditOrders): Column<[number, number]>[] {
  const coordinate = (k: 0 | 1): Column<[number, number]> => ({
    header: k === 0 ? "Latitude" : "Longitude",
    cell: ([lat, lon], i) => (
      <VertexInput
        label={`Vertex ${i + 1} ${k === 0 ? "latitude" : "longitude"}`}
        value={k === 0 ? lat : lon}
        onChange={(n) => editOrders((o) => setVertex(o, id, i, k === 0 ? [n, lon] : [lat, n]), `area:${id}:v${i}:${k}`)}
      />
    ),
  });
  return [{ header: "#", cell: (_, i) => i + 1 }, coordinate(0), coordinate(1)];
}

/** A number input that keeps partial text ("36.", "-") while typing. */
function VertexInput({ label, value, onChange }: { label: string; value: number; onChange: (n: number) => void }) {
  const [text, setText] = useState(String(value));
  const last = useRef(value);
  if (last.current !== value && Number(text) !== value) {
    last.current = value;
    setText(String(value));
  }
  return (
    <input
      type="number"
      step="any"
      aria-label={label}
      value={text}
      onChange={(e) => {
        setText(e.target.value);
        const n = parseNumber(e.target.value);
        if (n !== undefined) {
          last.current = n;
          onChange(n);
        }
      }}
    />
  );
}
