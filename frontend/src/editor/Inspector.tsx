/** The editor's side panels: findings, the goal inspector and the constraints panel. */
import type { Node } from "@xyflow/react";
import { memo, useCallback, useEffect, useMemo, useState } from "react";

import type { Finding } from "../api/client";
import {
  addConstraint,
  deleteConstraint,
  envelopeToText,
  type GoalSpec,
  goals,
  markersBySubject,
  type Orders,
  OUTCOME_LABEL,
  OUTCOME_LETTER,
  OUTCOMES,
  parseEnvelope,
  setSuccessor,
  startIds,
  terminals,
  toggleScope,
  updateConstraint,
  updateGoal,
} from "./graph";
import { knownQuantities } from "./expr";
import { CommitField, CommitSelect, ExprField, Picker } from "./fields";
import { paramsToText, parseParams } from "./model";
import { idAndTitle, successorChoices } from "./pickers";
import { useEditor, useEditorApi } from "./store";
import { BehaviourPicker } from "./VehiclePicker";
import { groupFindings, SUBJECTS_SHOWN } from "./findingGroups";
import { RefusedNote } from "./RefusedNote";

export type EditOrders = (change: (o: Orders) => Orders, group?: string) => void;

/** Items listed before "Show all": a long list (one per unreachable goal) renders late. */
const FINDINGS_SHOWN = 50;

/** The editor's findings, grouped (findingGroups.ts: errors first, each loop once, long subject
 * lists folded), each item a button that selects its subjects; a save the server refused heads
 * the list. Memoised, so that the renders that follow an edit do not rebuild a long list. */
export const FindingsList = memo(function FindingsList({
  findings,
  onPick,
  refused,
}: {
  findings: Finding[];
  onPick: (f: Finding, subjects: string[]) => void;
  refused?: string | null;
}) {
  const [all, setAll] = useState(false);
  const groups = useMemo(() => groupFindings(findings), [findings]);
  let budget = all ? Infinity : FINDINGS_SHOWN;
  const total = groups.reduce((n, g) => n + g.items.length, 0);
  return (
    <>
      {refused && (
        <p className="refused" role="alert" data-testid="findings-refused">
          Not saved: {refused}
        </p>
      )}
      <div className="editor-findings" data-testid="editor-findings">
        {groups.map((g) => {
          if (budget <= 0) return null;
          const items = g.items.slice(0, budget);
          budget -= items.length;
          return (
            <section key={g.key} className="finding-group" aria-label={`${g.code} ${g.severity}s`}>
              <h4>
                <code>{g.code}</code> {g.severity === "error" ? "errors" : "warnings"} ({g.items.length})
              </h4>
              <ul>
                {items.map((item) => (
                  <li key={item.key}>
                    <button type="button" className={`finding finding-${item.severity}`} onClick={() => onPick(item.findings[0]!, item.subjects)}>
                      <code>{item.code}</code> {item.severity}: {item.message}
                      {item.subjects.length > 0 && item.subjects.length <= SUBJECTS_SHOWN && <span className="hint"> ({item.subjects.join(", ")})</span>}
                    </button>
                    {item.subjects.length > SUBJECTS_SHOWN && (
                      <details className="finding-subjects">
                        <summary>
                          {item.subjects.slice(0, SUBJECTS_SHOWN).join(", ")} and {item.subjects.length - SUBJECTS_SHOWN} more
                        </summary>
                        <p className="subject-list">{item.subjects.join(", ")}</p>
                      </details>
                    )}
                  </li>
                ))}
              </ul>
            </section>
          );
        })}
      </div>
      {!all && total > FINDINGS_SHOWN && (
        <button type="button" onClick={() => setAll(true)} data-testid="findings-show-all">
          Show all {total} findings
        </button>
      )}
    </>
  );
});

// Length: every field of a goal in one fieldset, in the order the orders format lists them.
export const GoalInspector = memo(function GoalInspector({
  goal,
  orders,
  editOrders,
  titleRef,
  markers,
  findings,
}: {
  goal: GoalSpec;
  orders: Orders;
  editOrders: EditOrders;
  titleRef: React.RefObject<HTMLInputElement | null>;
  markers: ReturnType<typeof markersBySubject>;
  findings: Finding[];
}) {
  const id = goal.id;
  const set = (patch: Partial<GoalSpec>, group?: string) => editOrders((o) => updateGoal(o, id, patch), group);
  const areas = orders.areas ?? [];
  const successors = useMemo(() => successorChoices(goals(orders), terminals(orders)), [orders]);
  const [requires, setRequires] = useState((goal.requires ?? []).join(", "));
  const [envelope, setEnvelope] = useState(envelopeToText(goal.envelope));
  const [envelopeError, setEnvelopeError] = useState("");
  const mark = markers.get(id);
  const costValue = (key: "energy_wh" | "duration_s") => goal.cost?.[key] ?? "";
  const setCost = (key: "energy_wh" | "duration_s", text: string) => {
    const cost = { ...(goal.cost ?? {}) };
    if (text === "") delete cost[key];
    else cost[key] = Number(text);
    set({ cost: Object.keys(cost).length > 0 ? cost : undefined }, `g:${id}:cost:${key}`);
  };
  return (
    <fieldset className="inspector">
      <legend>
        Goal <code>{id}</code>
      </legend>
      {mark && (
        <p className={`message ${mark.severity === "error" ? "error" : ""}`}>Findings: {mark.codes.join(", ")}</p>
      )}
      <label htmlFor="goal-title">Title</label>
      <input id="goal-title" ref={titleRef} value={goal.title ?? ""} onChange={(e) => set({ title: e.target.value }, `g:${id}:title`)} />
      <RefusedNote fieldId="goal-title" />
      <label className="check">
        <input
          type="checkbox"
          checked={startIds(orders).includes(id)}
          onChange={(e) => editOrders((o) => ({ ...o, start: e.target.checked ? id : null }))}
        />{" "}
        Start goal
      </label>
      <BehaviourPicker
        value={goal.behavior ?? ""}
        vehicle={orders.vehicle ?? undefined}
        carried={orders.vehicles ?? []}
        onChange={(behavior) => set({ behavior })}
      />
      <label htmlFor="goal-area">Area</label>
      <CommitSelect id="goal-area" value={goal.area ?? ""} onCommit={(v) => set({ area: v || undefined })}>
        <option value="">— none —</option>
        {goal.area && !areas.some((a) => a.id === goal.area) && <option value={goal.area}>{goal.area} (unknown)</option>}
        {areas.map((a) => (
          <option key={a.id} value={a.id}>
            {a.title ? `${a.id}: ${a.title}` : a.id}
          </option>
        ))}
      </CommitSelect>
      <label htmlFor="goal-requires">Requires (comma-separated)</label>
      <input
        id="goal-requires"
        value={requires}
        onChange={(e) => setRequires(e.target.value)}
        onBlur={() => {
          const list = requires.split(",").map((s) => s.trim()).filter(Boolean);
          if (list.join(",") !== (goal.requires ?? []).join(",")) set({ requires: list.length > 0 ? list : undefined });
        }}
      />
      <FieldFindings findings={findings} subject={id} codes={["M7"]} />
      <label htmlFor="goal-envelope">Envelope (one "quantity min max" per line)</label>
      <textarea
        id="goal-envelope"
        rows={2}
        value={envelope}
        aria-invalid={!!envelopeError}
        aria-describedby="goal-envelope-error"
        onChange={(e) => setEnvelope(e.target.value)}
        onBlur={() => {
          const parsed = parseEnvelope(envelope);
          setEnvelopeError(parsed.error ?? "");
          if (parsed.envelope && envelopeToText(parsed.envelope) !== envelopeToText(goal.envelope)) {
            set({ envelope: Object.keys(parsed.envelope).length > 0 ? parsed.envelope : undefined });
          }
        }}
      />
      <span id="goal-envelope-error" className="field-error">
        {envelopeError}
      </span>
      <FieldFindings findings={findings} subject={id} codes={["CONTRADICTION"]} />
      <CommitField
        id="goal-params"
        label='Parameters (one "name value" per line)'
        multiline
        value={paramsToText(goal.params)}
        onCommit={(text) => {
          const parsed = parseParams(text);
          if (parsed.error) return parsed.error;
          set({ params: parsed.params && Object.keys(parsed.params).length > 0 ? parsed.params : undefined });
        }}
      />
      <div className="pair">
        <span>
          <label htmlFor="goal-energy">Energy (Wh)</label>
          <input id="goal-energy" type="number" min={0} value={costValue("energy_wh")} onChange={(e) => setCost("energy_wh", e.target.value)} />
        </span>
        <span>
          <label htmlFor="goal-duration">Duration (s)</label>
          <input id="goal-duration" type="number" min={0} value={costValue("duration_s")} onChange={(e) => setCost("duration_s", e.target.value)} />
        </span>
      </div>
      <FieldFindings findings={findings} subject={id} codes={["BUDGET", "NORM"]} />
      <FieldFindings findings={findings} subject={id} codes={["SINK", "G3", "G5", "G7"]} />
      {OUTCOMES.map((o) => {
        const current = goal.next?.[o];
        return (
          <Picker
            key={o}
            id={`goal-next-${o}`}
            testId={`goal-next-${o}-picker`}
            label={
              <>
                <span className={`outcome-letter outcome-${o}`}>{OUTCOME_LETTER[o]}</span> {OUTCOME_LABEL[o]} → next
              </>
            }
            value={typeof current === "string" ? current : ""}
            choices={successors}
            onCommit={(target) => editOrders((x) => setSuccessor(x, id, o, target || null))}
          />
        );
      })}
    </fieldset>
  );
});

/** The canvas's node click while a constraint's scope is being picked: the clicked goal goes
 * into the scope or out of it (terminals are not goals and are ignored). */
export function useScopePickClick(editOrders: EditOrders): (event: unknown, node: Node) => void {
  const store = useEditorApi();
  return useCallback(
    (_event: unknown, node: Node) => {
      const constraint = store.getState().scopePick;
      if (!constraint || node.type !== "goal") return;
      editOrders((o) => toggleScope(o, constraint, node.id));
    },
    [store, editOrders],
  );
}

/**
 * The constraints. A constraint's scope is the whole mission or a set of goals, ticked here
 * (each goal by id and title) or, with "Pick the scope on the graph", by clicking goals on the
 * canvas (the store's `scopePick` names the constraint; useScopePickClick toggles the goal).
 */
// Length: the constraints table: one row of fields per constraint with its scope pick.
export function ConstraintsPanel({
  orders,
  editOrders,
  markers,
  findings,
}: {
  orders: Orders;
  editOrders: EditOrders;
  markers: ReturnType<typeof markersBySubject>;
  findings: Finding[];
}) {
  const scopePick = useEditor((s) => s.scopePick);
  const onScopePick = useEditor((s) => s.pickScopeFor);
  // Escape ends picking; so does leaving the panel (unmount).
  useEffect(() => {
    if (!scopePick) return;
    const onKey = (e: KeyboardEvent) => {
      if (e.key === "Escape") onScopePick(null);
    };
    document.addEventListener("keydown", onKey);
    return () => document.removeEventListener("keydown", onKey);
  }, [scopePick, onScopePick]);
  useEffect(() => () => onScopePick(null), [onScopePick]);
  const list = orders.constraints ?? [];
  const known = useMemo(() => knownQuantities(orders), [orders]);
  return (
    <section aria-labelledby="constraints-title">
      <h3 id="constraints-title">Constraints</h3>
      {list.length === 0 && <p className="empty">No constraints.</p>}
      {list.map((c) => {
        const mark = markers.get(c.id);
        const whole = c.applies_to === undefined || c.applies_to === "mission";
        const picking = scopePick === c.id;
        const scoped = Array.isArray(c.applies_to) ? c.applies_to : [];
        return (
          <fieldset key={c.id} className={`constraint${picking ? " picking-scope" : ""}`}>
            <legend>
              Constraint <code>{c.id}</code> {mark && <span className={`badge ${mark.severity === "error" ? "bad" : "warn"}`}>{mark.codes.join(" ")}</span>}
            </legend>
            <label htmlFor={`c-${c.id}-text`}>{`${c.id} text`}</label>
            <input id={`c-${c.id}-text`} value={c.text ?? ""} onChange={(e) => editOrders((o) => updateConstraint(o, c.id, { text: e.target.value }), `c:${c.id}:text`)} />
            <RefusedNote fieldId={`c-${c.id}-text`} />
            <ExprField
              id={`c-${c.id}-expr`}
              label={`${c.id} expression`}
              value={c.expr ?? ""}
              known={known}
              onChange={(text) => editOrders((o) => updateConstraint(o, c.id, { expr: text }), `c:${c.id}:expr`)}
            />
            <RefusedNote fieldId={`c-${c.id}-expr`} />
            <FieldFindings findings={findings} subject={c.id} codes={null} />
            <div role="group" aria-label={`Scope of ${c.id}`} className="scope">
              <label className="check">
                <input
                  type="checkbox"
                  checked={whole}
                  onChange={(e) => editOrders((o) => updateConstraint(o, c.id, { applies_to: e.target.checked ? "mission" : [] }))}
                />{" "}
                {c.id} applies to the whole mission
              </label>
              {!whole &&
                goals(orders).map((g) => (
                  <label key={g.id} className="check">
                    <input
                      type="checkbox"
                      checked={Array.isArray(c.applies_to) && c.applies_to.includes(g.id)}
                      onChange={() => editOrders((o) => toggleScope(o, c.id, g.id))}
                      aria-label={`${c.id} applies to ${g.id}${g.title ? ` ${g.title}` : ""}`}
                    />{" "}
                    <span className="visually-hidden">{c.id} applies to </span>
                    {g.id}
                    {g.title && <span className="hint"> {g.title}</span>}
                  </label>
                ))}
              <p className="scope-pick">
                <button
                  type="button"
                  aria-pressed={picking}
                  data-testid={`pick-scope-${c.id}`}
                  onClick={() => onScopePick(picking ? null : c.id)}
                >
                  {picking ? `Done picking the scope of ${c.id}` : `Pick the scope of ${c.id} on the graph`}
                </button>
                {picking && (
                  <span className="hint" role="status" data-testid="scope-pick-status">
                    {" "}
                    Click goals on the graph to add them to {c.id} or take them out (Escape ends).{" "}
                    {scoped.length === 0 ? "No goal yet." : `Now: ${scoped.map((g) => idAndTitle(g, goals(orders).find((x) => x.id === g)?.title)).join("; ")}.`}
                  </span>
                )}
              </p>
            </div>
            <button type="button" className="danger" onClick={() => editOrders((o) => deleteConstraint(o, c.id))}>
              Delete constraint {c.id}
            </button>
          </fieldset>
        );
      })}
      <button type="button" onClick={() => editOrders((o) => addConstraint(o).orders)} data-testid="add-constraint">
        Add constraint
      </button>
    </section>
  );
}

/** Findings about one subject, shown beside the inspector field they concern (codes null: all). */
export function FieldFindings({ findings, subject, codes }: { findings: Finding[]; subject: string; codes: string[] | null }) {
  const mine = findings.filter((f) => f.subjects.includes(subject) && (codes === null || codes.includes(f.code)));
  if (mine.length === 0) return null;
  return (
    <ul className="field-findings" data-testid={`field-findings-${subject}`}>
      {mine.map((f, i) => (
        <li key={i} className={`finding-${f.severity}`}>
          {f.severity === "error" ? "✖" : "⚠"} <code>{f.code}</code> {f.message}
        </li>
      ))}
    </ul>
  );
}
