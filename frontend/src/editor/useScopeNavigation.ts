/** Moving the canvas between the parts of the orders (scope.ts): a team member's canvas, a
 * refinement's canvas; a scope an edit removed falls back to the member or the mission. */
import { useCallback, useEffect } from "react";

import { openingScope, ordersAt, type Scope, teamOf, TOP } from "./scope";
import { useEditor, useEditorApi } from "./store";

export interface ScopeNavigation {
  openScope: (next: Scope) => void;
  openRefinement: (id: string) => void;
}

export function useScopeNavigation(showLaidOutThenReady: () => void): ScopeNavigation {
  const store = useEditorApi();
  const orders = useEditor((s) => s.history.present.orders);
  const scope = useEditor((s) => s.scope);
  const replaceScope = useEditor((s) => s.replaceScope);
  const openScope = useCallback(
    (next: Scope) => {
      const { scope: now, showReady, openScope: enter, announce } = store.getState();
      if (next.member === now.member && next.path.join("/") === now.path.join("/")) return;
      showReady(false);
      enter(next);
      announce(next.path.length > 0 ? `Showing the refinement of ${next.path[next.path.length - 1]}.` : "Showing the mission.");
      // Fitted once the canvas carries the nodes of the new scope.
      window.requestAnimationFrame(() => window.requestAnimationFrame(showLaidOutThenReady));
    },
    [store, showLaidOutThenReady],
  );
  const openRefinement = useCallback(
    (id: string) => {
      const now = store.getState().scope;
      openScope({ member: now.member, path: [...now.path, id] });
    },
    [store, openScope],
  );
  useEffect(() => {
    if (ordersAt(orders, scope)) return;
    const member = { member: scope.member, path: [] };
    replaceScope(ordersAt(orders, member) && scope.member !== null ? member : teamOf(orders) ? openingScope(orders) : TOP);
  }, [orders, scope, replaceScope]);
  // A refused change of a goal's or terminal's field: select it, so that its inspector shows
  // the field with the refusal beside it.
  const refusal = useEditor((s) => s.refusal);
  const select = useEditor((s) => s.select);
  useEffect(() => {
    if (refusal?.select) select([refusal.select]);
  }, [refusal, select]);
  return { openScope, openRefinement };
}
