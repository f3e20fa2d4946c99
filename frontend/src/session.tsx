import { createContext, useContext } from "react";

import type { User } from "./api/client";
import { type Action, can } from "./roles";

export interface SessionContextValue {
  user: User;
  signOut: () => Promise<void>;
}

export const SessionContext = createContext<SessionContextValue | null>(null);

export function useSession(): SessionContextValue {
  const value = useContext(SessionContext);
  if (!value) throw new Error("useSession outside a signed-in page");
  return value;
}

/** Whether the signed-in user's role may do `action` (the server checks it again). */
export function useCan(action: Action): boolean {
  return can(useSession().user.role, action);
}
