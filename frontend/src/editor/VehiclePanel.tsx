/** The Vehicle panel: the vehicle profiles the orders carry (behaviours, sensors, envelope). */
import { CommitField } from "./fields";
import { envelopeToText, type Orders, parseEnvelope } from "./graph";
import { addFeature, addVehicle, deleteFeature, parseList, parseNumber, renameFeature, renameVehicle, targetVehicle, updateFeature, updateVehicle } from "./model";
import { MarkerBadge, type EditOrders, type Markers } from "./panels";

export function VehiclePanel({ orders, editOrders, markers }: { orders: Orders; editOrders: EditOrders; markers: Markers }) {
  const v = targetVehicle(orders);
  if (!v) return <NoVehicle orders={orders} editOrders={editOrders} />;
  const id = v.id;
  const set = (changes: Record<string, unknown>, group?: string) => editOrders((o) => updateVehicle(o, id, changes), group);
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
        <VehicleNumbers vehicle={v} set={set} />
      </fieldset>
      <h4>Features</h4>
      {(v.features ?? []).map((f) => (
        <FeatureFields key={f.id} orders={orders} vehicle={id} feature={f} editOrders={editOrders} />
      ))}
      <button type="button" onClick={() => editOrders((o) => addFeature(o, id).orders)}>
        Add feature
      </button>
    </section>
  );
}

type Vehicle = NonNullable<ReturnType<typeof targetVehicle>>;
type SetVehicle = (changes: Record<string, unknown>, group?: string) => void;

/** Speed, power and the budgets: numbers, each typed as a group (one undo step per pause). */
function VehicleNumbers({ vehicle: v, set }: { vehicle: Vehicle; set: SetVehicle }) {
  const num = (key: "speed_mps" | "power_w") => (v[key] ?? "") as number | "";
  const budget = (key: "energy_wh" | "duration_s") => v.budget?.[key] ?? "";
  const setBudget = (key: "energy_wh" | "duration_s", text: string) => {
    const b: Record<string, unknown> = { ...(v.budget ?? {}), [key]: parseNumber(text) };
    if (b[key] === undefined) delete b[key];
    set({ budget: b }, `v:budget:${key}`);
  };
  return (
    <>
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
    </>
  );
}

type Feature = NonNullable<Vehicle["features"]>[number];

/** One feature of the vehicle: its id, title, what it fulfils and measures. */
function FeatureFields({ orders, vehicle, feature: f, editOrders }: { orders: Orders; vehicle: string; feature: Feature; editOrders: EditOrders }) {
  return (
    <fieldset className="panel-box feature">
      <legend>
        Feature <code>{f.id}</code>
      </legend>
      <CommitField
        id={`feature-${f.id}-id`}
        label={`Feature ${f.id} id`}
        value={f.id}
        onCommit={(text) => {
          const r = renameFeature(orders, vehicle, f.id, text.trim());
          if (r.error) return r.error;
          editOrders(() => r.orders);
        }}
      />
      <label htmlFor={`feature-${f.id}-title`}>{`Feature ${f.id} title`}</label>
      <input
        id={`feature-${f.id}-title`}
        value={f.title ?? ""}
        onChange={(e) => editOrders((o) => updateFeature(o, vehicle, f.id, { title: e.target.value }), `f:${f.id}:title`)}
      />
      <CommitField
        id={`feature-${f.id}-fulfills`}
        label={`Feature ${f.id} fulfils (requirements, comma-separated)`}
        value={f.fulfills.join(", ")}
        onCommit={(text) => editOrders((o) => updateFeature(o, vehicle, f.id, { fulfills: parseList(text) }))}
      />
      <CommitField
        id={`feature-${f.id}-measures`}
        label={`Feature ${f.id} measures (quantities, comma-separated)`}
        value={f.measures.join(", ")}
        onCommit={(text) => editOrders((o) => updateFeature(o, vehicle, f.id, { measures: parseList(text) }))}
      />
      <button type="button" className="danger" onClick={() => editOrders((o) => deleteFeature(o, vehicle, f.id))}>
        Delete feature {f.id}
      </button>
    </fieldset>
  );
}

/** No profile in the orders: the vehicle named (or none) and a button that adds one. */
function NoVehicle({ orders, editOrders }: { orders: Orders; editOrders: EditOrders }) {
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
