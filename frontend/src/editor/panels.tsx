/**
 * Inspector panels for the parts of the orders beside the graph: the mission itself, areas
 * (with a plan view), quantities, the vehicle profile and norms. Every control is a labelled
 * input; ids, lists and multi-line specs commit on Enter or when focus leaves them.
 */
import { useMemo, useRef, useState } from "react";

import { numberPair } from "../api/pair";
import { CommitField, CommitSelect, ExprField } from "./fields";
import { VehiclePicker } from "./VehiclePicker";
import { RefusedNote } from "./RefusedNote";
import { envelopeToText, type Orders, parseEnvelope } from "./graph";
import {
  addArea,
  addFeature,
  addNorm,
  addQuantity,
  addVehicle,
  addVertex,
  areas,
  type AreaSpec,
  deleteArea,
  deleteFeature,
  deleteNorm,
  deleteQuantity,
  type LatLon,
  NORM_KINDS,
  normKind,
  type NormKind,
  norms,
  parseList,
  parseNumber,
  quantities,
  removeVertex,
  renameArea,
  renameFeature,
  renameVehicle,
  setNormKind,
  setVertex,
  targetVehicle,
  updateArea,
  updateFeature,
  updateMission,
  updateNorm,
  updateQuantity,
  updateVehicle,
} from "./model";
import { AreaChart } from "../map/AreaChart";

export type EditOrders = (change: (o: Orders) => Orders, group?: string) => void;
export type Markers = Map<string, { codes: string[]; severity: "error" | "warning" }>;

export function MarkerBadge({ markers, id }: { markers: Markers; id: string }) {
  const mark = markers.get(id);
  if (!mark) return null;
  return (
    <span className={`badge ${mark.severity === "error" ? "bad" : "warn"}`} data-testid={`field-markers-${id}`}>
      {mark.severity === "error" ? "✖ " : "⚠ "}
      {mark.codes.join(" ")}
    </span>
  );
}

// ---------------------------------------------------------------------------------------------

export function MissionPanel({ orders, editOrders }: { orders: Orders; editOrders: EditOrders }) {
  return (
    <fieldset className="panel-box">
      <legend>Mission</legend>
      <label htmlFor="mission-id">Mission id</label>
      <input id="mission-id" value={orders.id} readOnly aria-readonly="true" />
      <label htmlFor="mission-title">Mission title</label>
      <input
        id="mission-title"
        value={orders.title ?? ""}
        onChange={(e) => editOrders((o) => updateMission(o, { title: e.target.value }), "mission:title")}
      />
      <label htmlFor="mission-description">Mission description</label>
      <textarea
        id="mission-description"
        rows={3}
        value={orders.description ?? ""}
        onChange={(e) => editOrders((o) => updateMission(o, { description: e.target.value }), "mission:description")}
      />
      <VehiclePicker
        value={orders.vehicle ?? ""}
        carried={orders.vehicles ?? []}
        onChange={(vehicle) => editOrders((o) => updateMission(o, { vehicle }))}
      />
    </fieldset>
  );
}

// ---------------------------------------------------------------------------------------------

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
      <table className="vertices">
        <caption>Vertices of {id} (latitude, longitude in degrees)</caption>
        <thead>
          <tr>
            <th scope="col">#</th>
            <th scope="col">Latitude</th>
            <th scope="col">Longitude</th>
            <th scope="col">
              <span className="visually-hidden">Remove</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {polygon.map(numberPair).map(([lat, lon], i) => (
            <tr key={i}>
              <td>{i + 1}</td>
              {[0, 1].map((k) => (
                <td key={k}>
                  <VertexInput
                    label={`Vertex ${i + 1} ${k === 0 ? "latitude" : "longitude"}`}
                    value={k === 0 ? lat : lon}
                    onChange={(n) => editOrders((o) => setVertex(o, id, i, k === 0 ? [n, lon] : [lat, n]), `area:${id}:v${i}:${k}`)}
                  />
                </td>
              ))}
              <td>
                <button type="button" className="small" aria-label={`Remove vertex ${i + 1}`} onClick={() => editOrders((o) => removeVertex(o, id, i))}>
                  ✕
                </button>
              </td>
            </tr>
          ))}
        </tbody>
      </table>
      <button type="button" onClick={() => editOrders((o) => addVertex(o, id))}>
        Add vertex
      </button>{" "}
      <button type="button" className="danger" onClick={() => editOrders((o) => deleteArea(o, id))}>
        Delete area {id}
      </button>
    </fieldset>
  );
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

// ---------------------------------------------------------------------------------------------

export function QuantitiesPanel({ orders, editOrders }: { orders: Orders; editOrders: EditOrders }) {
  const all = quantities(orders);
  const [name, setName] = useState("");
  const [error, setError] = useState("");
  const add = () => {
    const r = addQuantity(orders, name.trim());
    setError(r.error ?? "");
    if (r.error) return;
    editOrders(() => r.orders);
    setName("");
  };
  return (
    <section aria-labelledby="quantities-title">
      <h3 id="quantities-title">Quantities</h3>
      <p className="hint">What constraints and envelopes measure. Built-in maritime quantities need no declaration.</p>
      <table className="quantities">
        <thead>
          <tr>
            <th scope="col">Name</th>
            <th scope="col">Title</th>
            <th scope="col">Type</th>
            <th scope="col">Unit</th>
            <th scope="col">Min</th>
            <th scope="col">Max</th>
            <th scope="col">
              <span className="visually-hidden">Delete</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {Object.entries(all).map(([q, spec]) => (
            <tr key={q}>
              <th scope="row">
                <code>{q}</code>
              </th>
              <td>
                <input aria-label={`${q} title`} value={spec.title ?? ""} onChange={(e) => editOrders((o) => updateQuantity(o, q, { title: e.target.value }), `q:${q}:title`)} />
              </td>
              <td>
                <CommitSelect
                  aria-label={`${q} type`}
                  value={spec.type ?? ""}
                  onCommit={(v) => editOrders((o) => updateQuantity(o, q, { type: v || undefined }))}
                >
                  <option value="">real (default)</option>
                  <option value="real">real</option>
                  <option value="integer">integer</option>
                  <option value="boolean">boolean</option>
                </CommitSelect>
              </td>
              <td>
                <input aria-label={`${q} unit`} size={5} value={spec.unit ?? ""} onChange={(e) => editOrders((o) => updateQuantity(o, q, { unit: e.target.value }), `q:${q}:unit`)} />
              </td>
              {(["min", "max"] as const).map((k) => (
                <td key={k}>
                  <input
                    aria-label={`${q} ${k}`}
                    type="number"
                    step="any"
                    value={spec[k] ?? ""}
                    onChange={(e) => editOrders((o) => updateQuantity(o, q, { [k]: parseNumber(e.target.value) }), `q:${q}:${k}`)}
                  />
                </td>
              ))}
              <td>
                <button type="button" className="small" aria-label={`Delete quantity ${q}`} onClick={() => editOrders((o) => deleteQuantity(o, q))}>
                  ✕
                </button>
              </td>
            </tr>
          ))}
        </tbody>
      </table>
      <form
        className="inline"
        onSubmit={(e) => {
          e.preventDefault();
          add();
        }}
      >
        <label htmlFor="new-quantity">New quantity name</label>
        <input id="new-quantity" value={name} onChange={(e) => setName(e.target.value)} aria-describedby="new-quantity-error" />
        <button type="submit">Add quantity</button>
        <span id="new-quantity-error" className="field-error">
          {error}
        </span>
      </form>
    </section>
  );
}

// ---------------------------------------------------------------------------------------------

export function VehiclePanel({ orders, editOrders, markers }: { orders: Orders; editOrders: EditOrders; markers: Markers }) {
  const v = targetVehicle(orders);
  if (!v) {
    return (
      <section aria-labelledby="vehicle-title">
        <h3 id="vehicle-title">Vehicle profile</h3>
        <p className="empty">
          {orders.vehicle
            ? `The orders name vehicle ${String(orders.vehicle)}; its profile comes from the server's registry unless you add one here.`
            : "The orders name no vehicle yet."}
        </p>
        <button type="button" onClick={() => editOrders((o) => addVehicle(o))}>
          Add vehicle profile
        </button>
      </section>
    );
  }
  const id = v.id;
  const set = (changes: Record<string, unknown>, group?: string) => editOrders((o) => updateVehicle(o, id, changes), group);
  const num = (key: "speed_mps" | "power_w") => (v[key] ?? "") as number | "";
  const budget = (key: "energy_wh" | "duration_s") => v.budget?.[key] ?? "";
  const setBudget = (key: "energy_wh" | "duration_s", text: string) => {
    const b: Record<string, unknown> = { ...(v.budget ?? {}), [key]: parseNumber(text) };
    if (b[key] === undefined) delete b[key];
    set({ budget: b }, `v:budget:${key}`);
  };
  return (
    <section aria-labelledby="vehicle-title">
      <h3 id="vehicle-title">
        Vehicle profile <MarkerBadge markers={markers} id={id} />
      </h3>
      <fieldset className="panel-box">
        <legend>
          Vehicle <code>{id}</code>
        </legend>
        <CommitField
          id="vehicle-id"
          label="Vehicle id"
          value={id}
          onCommit={(text) => {
            const r = renameVehicle(orders, id, text.trim());
            if (r.error) return r.error;
            editOrders(() => r.orders);
          }}
        />
        <label htmlFor="vehicle-name">Vehicle title</label>
        <input id="vehicle-name" value={v.title ?? ""} onChange={(e) => set({ title: e.target.value }, "v:title")} />
        <CommitField
          id="vehicle-behaviors"
          label="Trusted behaviours (comma-separated)"
          value={(v.behaviors ?? []).join(", ")}
          onCommit={(text) => set({ behaviors: parseList(text) })}
        />
        <CommitField
          id="vehicle-envelope"
          label='Vehicle envelope (one "quantity min max" per line)'
          multiline
          value={envelopeToText(v.envelope)}
          onCommit={(text) => {
            const parsed = parseEnvelope(text);
            if (parsed.error) return parsed.error;
            set({ envelope: parsed.envelope });
          }}
        />
        <div className="pair">
          <span>
            <label htmlFor="vehicle-speed">Speed (m/s)</label>
            <input id="vehicle-speed" type="number" step="any" min={0} value={num("speed_mps")} onChange={(e) => set({ speed_mps: parseNumber(e.target.value) }, "v:speed")} />
          </span>
          <span>
            <label htmlFor="vehicle-power">Power (W)</label>
            <input id="vehicle-power" type="number" step="any" min={0} value={num("power_w")} onChange={(e) => set({ power_w: parseNumber(e.target.value) }, "v:power")} />
          </span>
        </div>
        <div className="pair">
          <span>
            <label htmlFor="vehicle-budget-energy">Energy budget (Wh)</label>
            <input id="vehicle-budget-energy" type="number" step="any" min={0} value={budget("energy_wh")} onChange={(e) => setBudget("energy_wh", e.target.value)} />
          </span>
          <span>
            <label htmlFor="vehicle-budget-time">Time budget (s)</label>
            <input id="vehicle-budget-time" type="number" step="any" min={0} value={budget("duration_s")} onChange={(e) => setBudget("duration_s", e.target.value)} />
          </span>
        </div>
      </fieldset>
      <h4>Features</h4>
      {(v.features ?? []).map((f) => (
        <fieldset key={f.id} className="panel-box feature">
          <legend>
            Feature <code>{f.id}</code>
          </legend>
          <CommitField
            id={`feature-${f.id}-id`}
            label={`Feature ${f.id} id`}
            value={f.id}
            onCommit={(text) => {
              const r = renameFeature(orders, id, f.id, text.trim());
              if (r.error) return r.error;
              editOrders(() => r.orders);
            }}
          />
          <label htmlFor={`feature-${f.id}-title`}>{`Feature ${f.id} title`}</label>
          <input
            id={`feature-${f.id}-title`}
            value={f.title ?? ""}
            onChange={(e) => editOrders((o) => updateFeature(o, id, f.id, { title: e.target.value }), `f:${f.id}:title`)}
          />
          <CommitField
            id={`feature-${f.id}-fulfills`}
            label={`Feature ${f.id} fulfils (requirements, comma-separated)`}
            value={f.fulfills.join(", ")}
            onCommit={(text) => editOrders((o) => updateFeature(o, id, f.id, { fulfills: parseList(text) }))}
          />
          <CommitField
            id={`feature-${f.id}-measures`}
            label={`Feature ${f.id} measures (quantities, comma-separated)`}
            value={f.measures.join(", ")}
            onCommit={(text) => editOrders((o) => updateFeature(o, id, f.id, { measures: parseList(text) }))}
          />
          <button type="button" className="danger" onClick={() => editOrders((o) => deleteFeature(o, id, f.id))}>
            Delete feature {f.id}
          </button>
        </fieldset>
      ))}
      <button type="button" onClick={() => editOrders((o) => addFeature(o, id).orders)}>
        Add feature
      </button>
    </section>
  );
}

// ---------------------------------------------------------------------------------------------

export function NormsPanel({ orders, editOrders, markers, known }: { orders: Orders; editOrders: EditOrders; markers: Markers; known: string[] }) {
  const list = norms(orders);
  const contexts = useMemo(() => [...new Set(areas(orders).flatMap((a) => a.contexts ?? []))], [orders]);
  return (
    <section aria-labelledby="norms-title">
      <h3 id="norms-title">Norms</h3>
      {list.length === 0 && <p className="empty">No norms.</p>}
      <datalist id="context-options">
        {contexts.map((c) => (
          <option key={c} value={c} />
        ))}
      </datalist>
      {list.map((n) => {
        const kind = normKind(n);
        return (
          <fieldset key={n.id} className="panel-box">
            <legend>
              Norm <code>{n.id}</code> <MarkerBadge markers={markers} id={n.id} />
            </legend>
            <label htmlFor={`norm-${n.id}-context`}>{`Norm ${n.id} context`}</label>
            <input
              id={`norm-${n.id}-context`}
              list="context-options"
              value={n.context ?? ""}
              onChange={(e) => editOrders((o) => updateNorm(o, n.id, { context: e.target.value }), `n:${n.id}:context`)}
            />
            <RefusedNote fieldId={`norm-${n.id}-context`} />
            <label htmlFor={`norm-${n.id}-kind`}>{`Norm ${n.id} kind`}</label>
            <CommitSelect id={`norm-${n.id}-kind`} value={kind} onCommit={(v) => editOrders((o) => setNormKind(o, n.id, v as NormKind))}>
              {NORM_KINDS.map((k) => (
                <option key={k} value={k}>
                  {k}
                </option>
              ))}
            </CommitSelect>
            <ExprField
              id={`norm-${n.id}-expr`}
              label={`Norm ${n.id} expression`}
              value={n[kind] ?? ""}
              known={known}
              onChange={(text) => editOrders((o) => updateNorm(o, n.id, { [kind]: text }), `n:${n.id}:expr`)}
            />
            <RefusedNote fieldId={`norm-${n.id}-expr`} />
            <label htmlFor={`norm-${n.id}-text`}>{`Norm ${n.id} text`}</label>
            <input
              id={`norm-${n.id}-text`}
              value={n.text ?? ""}
              onChange={(e) => editOrders((o) => updateNorm(o, n.id, { text: e.target.value }), `n:${n.id}:text`)}
            />
            <RefusedNote fieldId={`norm-${n.id}-text`} />
            <button type="button" className="danger" onClick={() => editOrders((o) => deleteNorm(o, n.id))}>
              Delete norm {n.id}
            </button>
          </fieldset>
        );
      })}
      <button type="button" onClick={() => editOrders((o) => addNorm(o).orders)}>
        Add norm
      </button>
    </section>
  );
}
