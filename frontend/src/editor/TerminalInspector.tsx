/** The inspector of a selected terminal: its title, kind and (in a refinement) the outcome of the
 * refined goal it returns. */
import { CommitSelect } from "./fields";
import { type Orders, type terminals, updateTerminal } from "./graph";
import { RefusedNote } from "./RefusedNote";
import { isOutcome, setReturns } from "./scope";
import type { EditOrders } from "./useEditing";

type Terminal = ReturnType<typeof terminals>[number];

export function TerminalInspector({ terminal, editOrders, returnsOf }: { terminal: Terminal; editOrders: EditOrders; returnsOf: string | null }) {
  const returns = (terminal as { returns?: unknown }).returns;
  return (
    <fieldset className="inspector">
      <legend>Terminal {terminal.id}</legend>
      <label htmlFor="terminal-title">Title</label>
      <input
        id="terminal-title"
        value={terminal.title ?? ""}
        onChange={(e) => editOrders((o: Orders) => updateTerminal(o, terminal.id, { title: e.target.value }), `t:${terminal.id}:title`)}
      />
      <RefusedNote fieldId="terminal-title" />
      <label htmlFor="terminal-kind">Kind</label>
      <CommitSelect id="terminal-kind" value={terminal.kind} onCommit={(kind) => editOrders((o) => updateTerminal(o, terminal.id, { kind: kind as "complete" | "abort" }))}>
        <option value="complete">complete</option>
        <option value="abort">abort</option>
      </CommitSelect>
      {returnsOf !== null && (
        <>
          <label htmlFor="terminal-returns">Returns (the outcome of {returnsOf})</label>
          <CommitSelect
            id="terminal-returns"
            value={isOutcome(returns) ? String(returns) : ""}
            onCommit={(next) => isOutcome(next) && editOrders((o) => setReturns(o, terminal.id, next))}
          >
            <option value="" disabled>
              nothing (REFINE)
            </option>
            <option value="succeed">succeed</option>
            <option value="fail">fail</option>
            <option value="violate">violate</option>
          </CommitSelect>
        </>
      )}
    </fieldset>
  );
}
