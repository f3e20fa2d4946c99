/**
 * Who may decide, from the log, the browser's copy of backend
 * approvals/role_rules.py (both run the vectors in __fixtures__/roles.json). The users table is
 * not evidence (a database writer can promote an operator there); the log holds every account's
 * creation with its role, role change, disabling and password reset. A decision counts only from
 * someone the log shows as an enabled supervisor at that entry, and an account change only from
 * someone it shows as an admin (or the system: no actor). Pure: events in, problems out.
 */
export interface RoleEvent {
  kind?: string;
  actor?: unknown;
  mission?: unknown;
  detail?: Record<string, unknown>;
}

interface LoggedRole {
  role: string;
  at: number;
  disabledAt: number | null;
}

const DECIDING_KINDS = new Set(["approval.approved", "approval.rejected", "approval.revoked"]);
const ACCOUNT_KINDS = new Set(["user.created", "user.updated", "user.password_changed"]);

function decisionProblem(roles: Map<string, LoggedRole>, ungranted: Map<string, number>, user: string): string | null {
  const logged = roles.get(user);
  const entry = ungranted.get(user);
  if (!logged && entry !== undefined) return `the log gave ${user} no role (log entry ${entry} was not made by an admin)`;
  if (!logged) return `the log never created ${user} or gave them a role`;
  if (logged.role !== "supervisor") return `the log made ${user} ${logged.role} in log entry ${logged.at}`;
  if (logged.disabledAt !== null) return `the log disabled ${user} in log entry ${logged.disabledAt}`;
  return null;
}

function grantProblem(roles: Map<string, LoggedRole>, actor: unknown): string | null {
  if (actor === null || actor === undefined) return null; // the system: `countersign users create`
  const logged = roles.get(String(actor));
  if (!logged) return `the log never created ${String(actor)} or gave them a role`;
  if (logged.role !== "admin") return `the log made ${String(actor)} ${logged.role} in log entry ${logged.at}`;
  if (logged.disabledAt !== null) return `the log disabled ${String(actor)} in log entry ${logged.disabledAt}`;
  return null;
}

/** One problem per decision by someone the log did not make an enabled supervisor, and per
 * account change by someone it did not make an admin (such a change gives no role). */
export function checkRoles(events: RoleEvent[]): string[] {
  const problems: string[] = [];
  const roles = new Map<string, LoggedRole>();
  const ungranted = new Map<string, number>(); // accounts created only by a non-admin
  events.forEach((event, index) => {
    const kind = String(event.kind ?? "");
    const { actor } = event;
    const detail = event.detail ?? {};
    if (DECIDING_KINDS.has(kind) && actor !== null && actor !== undefined) {
      const why = decisionProblem(roles, ungranted, String(actor));
      if (why !== null) problems.push(`log entry ${index} (${kind}) by ${String(actor)}, but ${why}: only an enabled supervisor decides`);
      return;
    }
    if (!ACCOUNT_KINDS.has(kind) || typeof detail.user !== "string") return;
    const user = detail.user;
    if (kind === "user.password_changed" && detail.by === "self" && actor === user) return;
    const why = grantProblem(roles, actor);
    if (why !== null) {
      if (!ungranted.has(user)) ungranted.set(user, index);
      problems.push(`log entry ${index} (${kind}) by ${String(actor)} changes the account of ${user}, but ${why}: only an admin changes accounts, so it gives no role`);
      return;
    }
    const before = roles.get(user);
    const role = detail.role;
    if (kind === "user.created" || (typeof role === "string" && !before)) {
      roles.set(user, { role: String(role), at: index, disabledAt: null });
    } else if (before) {
      let next = before;
      if (typeof role === "string" && role !== next.role) next = { ...next, role, at: index };
      if (detail.disabled === true && next.disabledAt === null) next = { ...next, disabledAt: index };
      else if (detail.disabled === false) next = { ...next, disabledAt: null };
      roles.set(user, next);
    }
  });
  return problems;
}
