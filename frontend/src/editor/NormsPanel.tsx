/** The Norms panel: the norms (obligations, prohibitions, permissions) and their conditions. */
import { useMemo } from "react";

import { CommitSelect, ExprField } from "./fields";
import { RefusedNote } from "./RefusedNote";
import { type Orders } from "./graph";
import { addNorm, areas, deleteNorm, NORM_KINDS, normKind, type NormKind, norms, setNormKind, updateNorm } from "./model";
import { MarkerBadge, type EditOrders, type Markers } from "./panels";

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
      {list.map((n) => (
        <NormFields key={n.id} norm={n} editOrders={editOrders} markers={markers} known={known} />
      ))}
      <button type="button" onClick={() => editOrders((o) => addNorm(o).orders)}>
        Add norm
      </button>
    </section>
  );
}

type Norm = ReturnType<typeof norms>[number];

/** One norm: its context, kind, expression and text. */
function NormFields({ norm: n, editOrders, markers, known }: { norm: Norm; editOrders: EditOrders; markers: Markers; known: string[] }) {
  const kind = normKind(n);
  return (
    <fieldset className="panel-box">
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
}
