/** Above a selected goal's inspector: focus on its neighbourhood, its refinement (open, add,
 * remove) and its meeting id with who else meets there (teams). */
import { type GoalSpec, goals, type Orders } from "./graph";
import { patch } from "./model";
import { addRefinement, removeRefinement, teamOf } from "./scope";
import { useEditor } from "./store";
import type { EditorActions } from "./useEditorActions";
import type { EditOrders } from "./useEditing";

/** Who else meets at a meeting: "Meets vehicle-2 at G2 (Rendezvous ...)", or that nobody does. */
function partnersText(team: { vehicle: string; orders: Orders }[], member: number | null, meet: string): string {
  const others = team.flatMap((m, i) =>
    i === member ? [] : goals(m.orders).filter((g) => g.meet === meet).map((g) => `${m.vehicle} at ${g.id}${g.title ? ` (${g.title})` : ""}`),
  );
  return others.length > 0 ? `Meets ${others.join(" and ")}.` : `No other vehicle names meeting ${meet}: nobody will come (TEAM).`;
}

export function GoalRows({ goal, editOrders, actions }: { goal: GoalSpec; editOrders: EditOrders; actions: EditorActions }) {
  const focus = useEditor((s) => s.focus);
  return (
    <>
      <p className="focus-row">
        {focus === goal.id ? (
          <button type="button" onClick={() => actions.focusOn(null)} data-testid="unfocus-goal">
            Show the whole graph
          </button>
        ) : (
          <button type="button" onClick={() => actions.focusOn(goal.id)} data-testid="focus-goal">
            Focus this goal (F)
          </button>
        )}
      </p>
      <p className="focus-row" data-testid="refinement-row">
        {goal.refines ? (
          <>
            <button type="button" onClick={() => actions.openRefinement(goal.id)} data-testid="open-refinement">
              Open refinement
            </button>{" "}
            <button type="button" onClick={() => editOrders((o) => removeRefinement(o, goal.id))} data-testid="remove-refinement">
              Remove refinement
            </button>
          </>
        ) : (
          <button type="button" onClick={() => editOrders((o) => addRefinement(o, goal.id))} data-testid="add-refinement">
            Add refinement
          </button>
        )}
      </p>
      <MeetRow goal={goal} editOrders={editOrders} />
    </>
  );
}

function MeetRow({ goal, editOrders }: { goal: GoalSpec; editOrders: EditOrders }) {
  const team = teamOf(useEditor((s) => s.history.present.orders));
  const scope = useEditor((s) => s.scope);
  if (!(team || goal.meet || goal.behavior === "rendezvous")) return null;
  const setMeet = (meet: string) => editOrders((o) => ({ ...o, goals: goals(o).map((g) => (g.id === goal.id ? patch(g, { meet }) : g)) }), `g:${goal.id}:meet`);
  return (
    <p className="inspector-meet">
      <label htmlFor="goal-meet">Meeting id (rendezvous with the team)</label>
      <input id="goal-meet" value={goal.meet ?? ""} onChange={(e) => setMeet(e.target.value.trim())} data-testid="goal-meet" />
      {team && goal.meet && scope.path.length === 0 && (
        <span className="hint" data-testid="meet-partners">
          {partnersText(team, scope.member, goal.meet)}
        </span>
      )}
    </p>
  );
}
