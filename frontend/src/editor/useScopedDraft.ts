/** The draft as the canvas shows it at the editor's scope (scope.ts): the orders and positions
 * of the mission, a team member or a refinement, with local ids. */
import { useMemo } from "react";

import type { Orders } from "./graph";
import { layoutAt, memberAt, ordersAt, prefixOf, type Scope, teamOf, withLayoutAt, withOrdersAt } from "./scope";
import { type Draft, useEditor } from "./store";

export interface ScopedDraft extends Draft {
  /** The prefix of full ids ("" at the mission, "auv-1/G1/" inside a member's G1). */
  prefix: string;
  team: boolean;
  /** Whether the canvas shows a refinement (its terminals return the parent's outcomes). */
  refinement: boolean;
}

function isWhole(scope: Scope): boolean {
  return scope.member === null && scope.path.length === 0;
}

export function scopedDraft(draft: Draft, scope: Scope): ScopedDraft {
  const team = teamOf(draft.orders) !== null;
  if (isWhole(scope) && !team) return { ...draft, prefix: "", team, refinement: false };
  const orders = ordersAt(draft.orders, scope) ?? memberAt(draft.orders, scope);
  const prefix = prefixOf(draft.orders, scope);
  return { orders, layout: layoutAt(draft.layout, prefix, orders), prefix, team, refinement: scope.path.length > 0 };
}

/** A change of the scoped draft applied to the whole draft. */
export function applyScoped(draft: Draft, scope: Scope, change: (d: Draft) => Draft): Draft {
  if (isWhole(scope) && teamOf(draft.orders) === null) return change(draft);
  const view = scopedDraft(draft, scope);
  const next = change({ orders: view.orders, layout: view.layout });
  return {
    orders: next.orders === view.orders ? draft.orders : withOrdersAt(draft.orders, scope, next.orders),
    layout: next.layout === view.layout ? draft.layout : withLayoutAt(draft.layout, view.prefix, next.layout),
  };
}

/** A change of the orders at the scope's member (its vehicle, constraints, areas...). */
export function applyAtMember(orders: Orders, scope: Scope, change: (o: Orders) => Orders): Orders {
  if (scope.member === null) return change(orders);
  const at = { member: scope.member, path: [] };
  return withOrdersAt(orders, at, change(memberAt(orders, at)));
}

export function useScopedDraft(): ScopedDraft {
  const present = useEditor((s) => s.history.present);
  const scope = useEditor((s) => s.scope);
  return useMemo(() => scopedDraft(present, scope), [present, scope]);
}
