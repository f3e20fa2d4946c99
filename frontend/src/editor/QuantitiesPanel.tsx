/** The Quantities panel: the quantities the expressions read, with their units and ranges. */
import { useState } from "react";

import { CommitSelect } from "./fields";
import { type Orders } from "./graph";
import { addQuantity, deleteQuantity, parseNumber, quantities, updateQuantity } from "./model";
import { type EditOrders } from "./panels";

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
            <QuantityRow key={q} name={q} spec={spec} editOrders={editOrders} />
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

type Quantity = ReturnType<typeof quantities>[string];

/** One quantity: its title, type, unit and range (typing is grouped: one undo step a pause). */
function QuantityRow({ name: q, spec, editOrders }: { name: string; spec: Quantity; editOrders: EditOrders }) {
  return (
    <tr>
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
  );
}
