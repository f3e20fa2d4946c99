/**
 * The goal graphs a review shows: the mission's graph and, under it, each refined
 * goal's refinement (its terminals say which outcome of the parent they return); for a team,
 * every member's graph with the meetings that link them and the TEAM findings. Text only.
 */
import type { Finding } from "../../api/client";
import type { GoalSpec, Orders } from "../../editor/graph";
import { type MemberSpec, teamOf } from "../../editor/scope";
import { OrdersGraph } from "./OrdersGraph";

type Refined = { id: string; title: string; full: string; orders: Orders; within: string };

/** Every refinement of the orders, outermost first, with the full id of its goal (`G1/G1.2`). */
export function refinementsOf(orders: Orders, prefix = ""): Refined[] {
  const out: Refined[] = [];
  for (const g of orders.goals ?? []) {
    const r = g.refines;
    if (!r) continue;
    const full = `${prefix}${g.id}`;
    const bound = r.within?.steps != null ? `${r.within.steps} steps` : r.within?.duration_s != null ? `${r.within.duration_s} s` : "";
    const within = bound ? `Bounded: at most ${bound}, then ${r.on_timeout ?? "fail"}.` : "";
    // A terminal's drawn title says which outcome of the parent it returns.
    // (Its own title is in the plain-language orders; a terminal's box holds about 19 characters.)
    const terminals = (r.terminals ?? []).map((t) => ({ ...t, title: `returns ${t.returns ?? "nothing"}` }));
    const inner: Orders = { ...r, id: g.id, terminals };
    out.push({ id: g.id, title: g.title ?? "", full, orders: inner, within });
    out.push(...refinementsOf({ ...r, id: g.id }, `${full}/`));
  }
  return out;
}

/** Meeting id -> the members' goals that name it. */
export function meetingsOf(team: MemberSpec[]): Map<string, { vehicle: string; goal: GoalSpec }[]> {
  const meetings = new Map<string, { vehicle: string; goal: GoalSpec }[]>();
  for (const m of team) {
    for (const goal of m.orders.goals ?? []) {
      if (!goal.meet) continue;
      meetings.set(goal.meet, [...(meetings.get(goal.meet) ?? []), { vehicle: m.vehicle, goal }]);
    }
  }
  return meetings;
}

function Refinements({ orders, prefix, label }: { orders: Orders; prefix: string; label: string }) {
  const refined = refinementsOf(orders, prefix);
  if (refined.length === 0) return null;
  return (
    <>
      {refined.map((r) => (
        <section key={r.full} className="review-refinement" data-testid={`review-refinement-${r.full}`} aria-label={`Refinement of ${r.full}`}>
          <h3>
            Refinement of {r.full}
            {r.title ? `: ${r.title}` : ""}
          </h3>
          <p className="hint">
            {r.full} is carried out as these steps (outside they read {r.full}/…); each end returns an outcome of {r.full}. {r.within}
          </p>
          <OrdersGraph orders={r.orders} label={`${label}, refinement of ${r.full}`} />
        </section>
      ))}
    </>
  );
}

export function MissionGraphs({ orders, label, findings }: { orders: Orders; label: string; findings: Finding[] }) {
  const team = teamOf(orders);
  if (!team) {
    return (
      <>
        <OrdersGraph orders={orders} label={label} />
        <Refinements orders={orders} prefix="" label={label} />
      </>
    );
  }
  const meetings = meetingsOf(team);
  const teamFindings = findings.filter((f) => f.code === "TEAM");
  return (
    <>
      <section className="review-team" aria-labelledby="review-meetings-title" data-testid="review-meetings">
        <h3 id="review-meetings-title">Team of {team.length} vehicles: meetings</h3>
        {meetings.size === 0 ? (
          <p className="empty">No goal names a meeting.</p>
        ) : (
          <ul>
            {[...meetings].map(([meet, at]) => (
              <li key={meet}>
                <strong>Meeting {meet}</strong>:{" "}
                {at.map((a) => `${a.vehicle} at ${a.goal.id}${a.goal.title ? ` (${a.goal.title})` : ""}`).join(" with ")}
              </li>
            ))}
          </ul>
        )}
        <h3>Team findings</h3>
        {teamFindings.length === 0 ? (
          <p className="verdict ok" data-testid="review-team-findings">
            No member can be left waiting at a meeting.
          </p>
        ) : (
          <ul data-testid="review-team-findings">
            {teamFindings.map((f, i) => (
              <li key={i} className="verdict bad">
                <strong>TEAM {f.severity}</strong>: {f.message}
              </li>
            ))}
          </ul>
        )}
      </section>
      {team.map((m, i) => (
        <section key={`${i}-${m.vehicle}`} className="review-member" aria-labelledby={`review-member-${i}`} data-testid={`review-member-${m.vehicle}`}>
          <h3 id={`review-member-${i}`}>
            Vehicle {m.vehicle}
            {m.orders.title ? `: ${m.orders.title}` : ""}
          </h3>
          <OrdersGraph orders={m.orders} label={`${label}, vehicle ${m.vehicle}`} />
          <Refinements orders={m.orders} prefix={`${m.vehicle}/`} label={`${label}, vehicle ${m.vehicle}`} />
        </section>
      ))}
    </>
  );
}
