/**
 * The part of the orders the canvas shows: the mission's own goals, a team member's
 * orders (one canvas per vehicle) or a goal's refinement (its own canvas of sub-goals and
 * terminals that return the parent's outcomes), nested. The draft stays whole: the editor reads
 * and edits the part in scope through these functions, so every edit goes through the one save
 * path and the orders JSON gains or changes `team[i].orders` and `refines`.
 *
 * Ids inside a refinement are local; outside they read `G1/G1.1`, and a team member's read
 * `auv-1/G3` (verify/refine.py, verify/team_report.py). Positions of the nodes in scope are kept
 * in the one layout under those full ids.
 */
import type { Finding, Schema } from "../api/client";
import { goals, type GoalSpec, type Layout, type Orders, OUTCOMES, type Outcome } from "./graph";
import { layeredLayout } from "./layout";

export type RefinementSpec = Schema<"Refinement">;

export interface Scope {
  /** The team member shown (its index in `team`), or null for orders without a team. */
  member: number | null;
  /** The refined goals opened, outermost first (local ids). */
  path: string[];
}
export const TOP: Scope = { member: null, path: [] };
export const SEP = "/";

/** A team member as the server's model declares it: a vehicle and its own orders. */
export type MemberSpec = Schema<"TeamMember">;

/** The team's members (each with its own orders), or null for one vehicle's orders. */
export function teamOf(orders: Orders): MemberSpec[] | null {
  const team = orders.team;
  if (!Array.isArray(team) || team.length === 0) return null;
  return team;
}

/** The scope a draft opens at: its first member for a team, else the mission. */
export function openingScope(orders: Orders): Scope {
  return teamOf(orders) ? { member: 0, path: [] } : TOP;
}

function memberOrders(orders: Orders, member: number | null): Orders | null {
  if (member === null) return orders;
  return teamOf(orders)?.[member]?.orders ?? null;
}

function withMemberOrders(orders: Orders, member: number | null, sub: Orders): Orders {
  if (member === null || !Array.isArray(orders.team)) return sub;
  return { ...orders, team: orders.team.map((m, i) => (i === member ? { ...m, orders: sub } : m)) };
}

/** A refinement read as orders (its goals, start and terminals; the rest stays as written),
 * the refined goal's id standing for the orders' id. */
export function refinementAsOrders(goal: GoalSpec): Orders | null {
  return goal.refines ? { ...goal.refines, id: goal.id } : null;
}

/** Orders edited at a refinement's scope written back as the refinement (without the id that
 * `refinementAsOrders` lent it). */
function ordersAsRefinement(sub: Orders): RefinementSpec {
  const { id: _lent, terminals, ...rest } = sub;
  return terminals ? { ...rest, terminals } : rest;
}

/** The orders at the scope's member (its own orders, with vehicle, constraints and areas). */
export function memberAt(orders: Orders, scope: Scope): Orders {
  return memberOrders(orders, scope.member) ?? orders;
}

/** The orders the canvas shows at this scope, or null when the scope no longer exists. */
export function ordersAt(orders: Orders, scope: Scope): Orders | null {
  let current = memberOrders(orders, scope.member);
  for (const id of scope.path) {
    const goal = current ? goals(current).find((g) => g.id === id) : undefined;
    current = goal ? refinementAsOrders(goal) : null;
  }
  return current;
}

function withPath(orders: Orders, path: string[], sub: Orders): Orders {
  if (path.length === 0) return sub;
  const [id, ...rest] = path;
  return {
    ...orders,
    goals: goals(orders).map((g) => {
      if (g.id !== id) return g;
      const inner = refinementAsOrders(g) ?? { id: g.id };
      return { ...g, refines: ordersAsRefinement(withPath(inner, rest, sub)) };
    }),
  };
}

/** The orders with the part at this scope replaced by `sub`. */
export function withOrdersAt(orders: Orders, scope: Scope, sub: Orders): Orders {
  const member = memberOrders(orders, scope.member);
  if (!member) return orders;
  return withMemberOrders(orders, scope.member, withPath(member, scope.path, sub));
}

/** The prefix of full ids at this scope: "" at the mission, "auv-1/" at a member, "G1/" inside G1. */
export function prefixOf(orders: Orders, scope: Scope): string {
  const member = scope.member === null ? null : teamOf(orders)?.[scope.member]?.vehicle;
  return [...(member ? [member] : []), ...scope.path].map((p) => `${p}${SEP}`).join("");
}

/** The positions at this scope, under local ids; nodes without one are laid out (not saved
 * until moved). */
export function layoutAt(layout: Layout, prefix: string, sub: Orders): Layout {
  const out: Layout = {};
  for (const [id, p] of Object.entries(layout)) {
    if (!id.startsWith(prefix)) continue;
    const local = id.slice(prefix.length);
    if (local && !local.includes(SEP)) out[local] = p;
  }
  if (prefix === "") return out;
  const ids = [...goals(sub).map((g) => g.id), ...(sub.terminals ?? []).map((t) => t.id)];
  if (ids.length > 0 && ids.some((id) => !out[id])) return { ...layeredLayout(sub, 1.6), ...out };
  return out;
}

/** The layout with the positions at this scope replaced by `sub` (local ids). */
export function withLayoutAt(layout: Layout, prefix: string, sub: Layout): Layout {
  if (prefix === "") {
    const kept = Object.fromEntries(Object.entries(layout).filter(([id]) => id.includes(SEP)));
    return { ...kept, ...sub };
  }
  const out: Layout = {};
  for (const [id, p] of Object.entries(layout)) {
    const local = id.startsWith(prefix) ? id.slice(prefix.length) : null;
    if (local !== null && local !== "" && !local.includes(SEP)) continue;
    out[id] = p;
  }
  for (const [id, p] of Object.entries(sub)) out[`${prefix}${id}`] = p;
  return out;
}

/** The findings that concern this scope: a subject inside it, the refined goal itself, and a
 * team's TEAM findings at every member. */
export function findingsAt(findings: Finding[], prefix: string, team: boolean): Finding[] {
  if (prefix === "") return findings;
  const self = prefix.slice(0, -1);
  return findings.filter(
    (f) => (team && f.code === "TEAM") || f.subjects.some((s) => s.startsWith(prefix) || s === self),
  );
}

/** Findings with subjects as the canvas at this scope names them (a subject deeper inside marks
 * the refined goal that holds it); subjects outside the scope are left out. */
export function localFindings(findings: Finding[], prefix: string): Finding[] {
  const out: Finding[] = [];
  for (const f of findings) {
    const subjects = f.subjects
      .filter((s) => s.startsWith(prefix))
      .map((s) => s.slice(prefix.length).split(SEP)[0]!)
      .filter(Boolean);
    if (subjects.length > 0) out.push({ ...f, subjects: [...new Set(subjects)] });
  }
  return out;
}

/** The outcome a refinement terminal of this kind returns by default. */
export function defaultReturn(kind: "complete" | "abort"): Outcome {
  return kind === "complete" ? "succeed" : "fail";
}

/** A goal's new refinement: one sub-goal whose three outcomes go to terminals returning the
 * parent's succeed, fail and violate. */
export function addRefinement(orders: Orders, goalId: string): Orders {
  return {
    ...orders,
    goals: goals(orders).map((g) => {
      if (g.id !== goalId || g.refines) return g;
      const first = `${goalId}.1`;
      const refines: RefinementSpec = {
        start: first,
        goals: [{ id: first, title: `First step of ${g.title || goalId}`, next: { succeed: "DONE", fail: "FAILED", violate: "HALT" } }],
        terminals: [
          { id: "DONE", kind: "complete", title: "Done", returns: "succeed" },
          { id: "FAILED", kind: "abort", title: "Failed", returns: "fail" },
          { id: "HALT", kind: "abort", title: "Constraint about to be violated", returns: "violate" },
        ],
      };
      return { ...g, refines };
    }),
  };
}

/** Removes a goal's refinement (the goal is carried out by its own behaviour again). */
export function removeRefinement(orders: Orders, goalId: string): Orders {
  return {
    ...orders,
    goals: goals(orders).map((g) => {
      if (g.id !== goalId) return g;
      const rest = { ...g };
      delete rest.refines;
      return rest;
    }),
  };
}

/** Sets what a refinement terminal returns. */
export function setReturns(orders: Orders, terminalId: string, returns: Outcome): Orders {
  return {
    ...orders,
    terminals: (orders.terminals ?? []).map((t) => (t.id === terminalId ? { ...t, returns } : t)),
  };
}

export function isOutcome(value: unknown): value is Outcome {
  return typeof value === "string" && (OUTCOMES as readonly string[]).includes(value);
}

/** Breadcrumbs: the mission (or the member's vehicle), then each refined goal opened. */
export function crumbsOf(orders: Orders, scope: Scope): { label: string; scope: Scope }[] {
  const team = teamOf(orders);
  const root = scope.member !== null && team ? `${team[scope.member]?.vehicle ?? "Member"}` : "Mission";
  const crumbs = [{ label: root, scope: { member: scope.member, path: [] as string[] } }];
  let current = memberOrders(orders, scope.member);
  scope.path.forEach((id, i) => {
    const goal = current ? goals(current).find((g) => g.id === id) : undefined;
    crumbs.push({ label: goal?.title ? `${id} ${goal.title}` : id, scope: { member: scope.member, path: scope.path.slice(0, i + 1) } });
    current = goal ? refinementAsOrders(goal) : null;
  });
  return crumbs;
}
