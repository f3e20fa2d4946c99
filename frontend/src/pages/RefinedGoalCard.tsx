/**
 * The current goal of a refined mission's rehearsal: the goal inside a refined goal that the
 * simulation flies (or that the s/f/c keys and buttons decide), its breadcrumb from the mission's
 * level down (G1 › G1.2), and the last time-out that ended a refinement. The rehearsal flies the
 * flat automaton the verifier reads, so the id may carry an unrolling mark (`G1/G1.2#3`: the
 * third goal commenced inside G1); the breadcrumb names the goals of the orders. Every title is
 * the orders' text, shown as text.
 */
import { OUTCOME_LABEL, type Outcome } from "../editor/graph";
import type { components } from "../api/schema";
import { stepPlace } from "./rehearsalOrder";
import "./refined-rehearsal.css";

type Refined = components["schemas"]["RefinedStatus"];
type Current = components["schemas"]["CurrentGoal"];

/** The last segment of a flat id without its marks: `G1/G1.2#3` -> G1.2. */
function localId(id: string): string {
  const parts = stepPlace(id).full.split("/");
  return parts[parts.length - 1] ?? id;
}

function clock(seconds: number): string {
  const s = Math.max(0, Math.round(seconds));
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  return h > 0 ? `${h} h ${String(m).padStart(2, "0")} min` : `${m} min ${String(s % 60).padStart(2, "0")} s`;
}

export function RefinedGoalCard({ refined, current }: { refined: Refined; current: Current | null }) {
  const inside = refined.inside;
  const timeout = refined.timeout;
  return (
    <section className="refined-goal" aria-label="Goal inside a refinement" data-testid="refined-goal">
      {current && inside.length > 0 ? (
        <>
          <nav aria-label="Refinement breadcrumb">
            <ol className="refined-breadcrumb" data-testid="refined-breadcrumb">
              {inside.map((p) => (
                <li key={p.id} title={p.title}>
                  {localId(p.id)}
                </li>
              ))}
              <li aria-current="step">{localId(current.id)}</li>
            </ol>
          </nav>
          <p className="refined-current" data-testid="refined-current">
            <code>{current.id}</code> {current.title}
            <span className="refined-parents">
              {" "}
              inside {inside.map((p) => p.title || localId(p.id)).join(" › ")}
            </span>
          </p>
        </>
      ) : (
        <p className="refined-current" data-testid="refined-current">
          {current ? "The current goal is on the mission's level." : "No goal is running."}
        </p>
      )}
      {timeout && (
        <p className="refined-timeout" role="status" data-testid="refined-timeout">
          Time-out: {timeout.title || timeout.goal} (<code>{timeout.goal}</code>) ended its refinement with{" "}
          {OUTCOME_LABEL[timeout.returns as Outcome] ?? timeout.returns} at {clock(timeout.t)}.
        </p>
      )}
    </section>
  );
}
