/** Above the canvas for teams and refinements: the team member shown and the breadcrumbs of the
 * refinement open (scope.ts). */
import { crumbsOf, type Scope, teamOf } from "./scope";
import { useEditor } from "./store";

export function ScopeBar({ openScope }: { openScope: (next: Scope) => void }) {
  const orders = useEditor((s) => s.history.present.orders);
  const scope = useEditor((s) => s.scope);
  const team = teamOf(orders);
  if (team === null && scope.path.length === 0) return null;
  return (
    <div className="editor-scope" data-testid="editor-scope">
      {team && (
        <div className="members" role="group" aria-label="Team member shown on the canvas">
          <span>Vehicle:</span>
          {team.map((m, i) => (
            <button type="button" key={`${i}-${m.vehicle}`} aria-pressed={scope.member === i} onClick={() => openScope({ member: i, path: [] })} data-testid={`member-${m.vehicle}`}>
              {m.vehicle}
            </button>
          ))}
        </div>
      )}
      {scope.path.length > 0 && <Breadcrumbs crumbs={crumbsOf(orders, scope)} openScope={openScope} />}
    </div>
  );
}

function Breadcrumbs({ crumbs, openScope }: { crumbs: { label: string; scope: Scope }[]; openScope: (next: Scope) => void }) {
  return (
    <nav aria-label="Refinement breadcrumbs" data-testid="breadcrumbs">
      <ol>
        {crumbs.map((c, i) =>
          i === crumbs.length - 1 ? (
            <li key={i}>
              <span aria-current="location" data-testid="crumb-current">
                {c.label}
              </span>
            </li>
          ) : (
            <li key={i}>
              <button type="button" className="link-button" onClick={() => openScope(c.scope)} data-testid={`crumb-${i}`}>
                {c.label}
              </button>
            </li>
          ),
        )}
      </ol>
    </nav>
  );
}
