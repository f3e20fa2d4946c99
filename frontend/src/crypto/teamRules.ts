/**
 * A team approval's member digests, checked in the browser as approvals/team_rules.py checks
 * them (both run the vectors in __fixtures__/team.json and name the same problems). One
 * approval signs a team's orders: the subject is the team's digest and `predicate.team` gives
 * every member's digest by vehicle (the member's orders alone, as countersign.orders/1), the
 * digest a vehicle loading only its own orders can check.
 */
import { jsonDigest } from "./canonical";

// The format a member's orders are hashed as: a member's orders carry none of their own.
const ORDERS_FORMAT = "countersign.orders/1";

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** Each member's orders digest by vehicle, or null when the orders hold no team. */
export async function memberOrdersDigests(orders: unknown): Promise<Map<string, string> | null> {
  const members = isRecord(orders) ? orders.team : undefined;
  if (!Array.isArray(members) || !members.every((m) => isRecord(m) && isRecord(m.orders))) return null;
  const digests = new Map<string, string>();
  for (const member of members as { vehicle?: unknown; orders: Record<string, unknown> }[]) {
    digests.set(String(member.vehicle), await jsonDigest({ ...member.orders, format: ORDERS_FORMAT }));
  }
  return digests;
}

/** Whether these orders or this predicate are a team's: only then is there a team check. */
export function isTeamApproval(orders: unknown, predicate: unknown): boolean {
  return (isRecord(orders) && orders.team !== undefined && orders.team !== null) || (isRecord(predicate) && predicate.team !== undefined && predicate.team !== null);
}

/** What is wrong with the member digests the predicate signs for these orders (the ones the
 * subject digest covers), each problem naming its member; empty when they are the team's. */
export async function teamProblems(orders: unknown, predicate: unknown): Promise<string[]> {
  const signed = isRecord(predicate) ? predicate.team : undefined;
  const actual = await memberOrdersDigests(orders);
  if (signed === undefined || signed === null) {
    return actual === null ? [] : ["the orders hold a team but the statement signs no member digests (predicate.team)"];
  }
  if (actual === null) return ["the statement signs a team's member digests (predicate.team) but the orders hold no team"];
  if (!isRecord(signed) || !Object.values(signed).every((v) => typeof v === "string")) {
    return ["the statement's predicate.team is not a map of vehicle to orders digest"];
  }
  const problems: string[] = [];
  for (const vehicle of actual.keys()) {
    if (!Object.hasOwn(signed, vehicle)) problems.push(`team member ${vehicle}: the statement signs no digest for it`);
  }
  for (const vehicle of Object.keys(signed)) {
    if (!actual.has(vehicle)) problems.push(`team member ${vehicle}: the statement signs a digest for it but the team has no such member`);
  }
  for (const [vehicle, digest] of actual) {
    if (Object.hasOwn(signed, vehicle) && signed[vehicle] !== digest) {
      problems.push(`team member ${vehicle}: the signed digest ${String(signed[vehicle])} is not that of its orders (${digest})`);
    }
  }
  return problems;
}
