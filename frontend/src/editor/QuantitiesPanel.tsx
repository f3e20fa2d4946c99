/** The Quantities panel: the quantities the expressions read, with their units and ranges. */
import { useState } from "react";

import type { Column } from "../components/DataTable";
import { EditableTable } from "../components/EditableTable";
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
      <EditableTable
        caption="Quantities"
        className="quantities"
        columns={quantityColumns(editOrders)}
        rows={Object.entries(all)}
        rowKey={([q]) => q}
        remove={{
          header: "Delete",
          text: () => "✕",
          label: ([q]) => `Delete quantity ${q}`,
          className: "small",
          onRemove: ([q]) => editOrders((o) => deleteQuantity(o, q)),
        }}
      />
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

/** One quantity a row: its title, type, unit and range (typing is grouped: one undo step a pause). */
function quantityColumns(editOrders: EditOrders): Column<[string, Quantity]>[] {
  const text = (key: "title" | "unit", size?: number): Column<[string, Quantity]> => ({
    header: key === "title" ? "Title" : "Unit",
    cell: ([q, spec]) => (
      <input aria-label={`${q} ${key}`} size={size} value={spec[key] ?? ""} onChange={(e) => editOrders((o) => updateQuantity(o, q, { [key]: e.target.value }), `q:${q}:${key}`)} />
    ),
  });
  const bound = (key: "min" | "max"): Column<[string, Quantity]> => ({
    header: key === "min" ? "Min" : "Max",
    cell: ([q, spec]) => (
      <input
        aria-label={`${q} ${key}`}
        type="number"
        step="any"
        value={spec[key] ?? ""}
        onChange={(e) => editOrders((o) => updateQuantity(o, q, { [key]: parseNumber(e.target.value) }), `q:${q}:${key}`)}
      />
    ),
  });
  return [
    { header: "Name", rowHeader: true, cell: ([q]) => <code>{q}</code> },
    text("title"),
    {
      header: "Type",
      cell: ([q, spec]) => (
        <CommitSelect aria-label={`${q} type`} value={spec.type ?? ""} onCommit={(v) => editOrders((o) => updateQuantity(o, q, { type: v || undefined }))}>
          <option value="">real (default)</option>
          <option value="real">real</option>
          <option value="integer">integer</option>
          <option value="boolean">boolean</option>
        </CommitSelect>
      ),
    },
    text("unit", 5),
    bound("min"),
    bound("max"),
  ];
}
