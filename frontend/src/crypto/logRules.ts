/**
 * Log-wide rules, the browser's copy of backend approvals/log_rules.py:
 * whatever the tables say, the logged events must describe a legal history. One decision per
 * submission, one active submission per version, a revocation only of an approved submission,
 * no signature by a key after the log revoked it, and (when the caller knows which entries it
 * holds envelopes for) an envelope for every logged decision; and no decision by its mission's
 * editor or submitter (dutyRules.ts) or by anyone the log did not make a supervisor
 * (roleRules.ts). Pure: events in, problems out.
 */
import { checkDuties } from "./dutyRules";
import { checkRoles } from "./roleRules";

export interface RuleEvent {
  kind?: string;
  actor?: unknown;
  mission?: unknown;
  detail?: Record<string, unknown>;
}

const DECISIONS = new Set(["approval.approved", "approval.rejected"]);

export function checkLog(events: RuleEvent[], enveloped?: Iterable<number>, scope?: string | null): string[] {
  const problems: string[] = [];
  const created = new Map<number, number>();
  const target = new Map<number, string>();
  const state = new Map<number, string>();
  const decided = new Map<number, number>();
  const active = new Map<string, number>();
  const revokedKeys = new Map<string, number>();
  const wanted = enveloped ? new Set(enveloped) : null;
  events.forEach((event, index) => {
    const kind = String(event.kind ?? "");
    const detail = event.detail ?? {};
    if (kind === "key.revoked") {
      const kid = String(detail.key_id);
      if (!revokedKeys.has(kid)) revokedKeys.set(kid, index);
      return;
    }
    const submission = detail.submission;
    if (!(kind.startsWith("submission.") || kind.startsWith("approval.")) || typeof submission !== "number") return;
    if (kind === "submission.created") {
      const key = JSON.stringify([event.mission ?? null, detail.version ?? null]);
      const [mission, version] = JSON.parse(key) as [unknown, unknown];
      if (created.has(submission)) {
        problems.push(`log entry ${index} creates submission ${submission} again (first in log entry ${created.get(submission)})`);
      }
      if (active.has(key)) {
        problems.push(
          `log entry ${index} submits ${String(mission)} version ${String(version)} while submission ${active.get(key)} is still active: one active submission per version`,
        );
      } else {
        active.set(key, submission);
      }
      created.set(submission, index);
      target.set(submission, key);
      state.set(submission, "submitted");
      return;
    }
    if (!created.has(submission)) {
      problems.push(`log entry ${index} (${kind}) concerns submission ${submission}, which the log never created`);
      return;
    }
    const now = state.get(submission)!;
    if (DECISIONS.has(kind)) {
      if (decided.has(submission)) {
        problems.push(`log entries ${decided.get(submission)} and ${index} both decide submission ${submission}: one decision per submission`);
      } else {
        if (now !== "submitted") problems.push(`log entry ${index} decides submission ${submission}, which was ${now}`);
        decided.set(submission, index);
      }
      state.set(submission, kind.slice("approval.".length));
    } else if (kind === "approval.revoked") {
      if (now !== "approved") problems.push(`log entry ${index} revokes submission ${submission}, which was ${now}, not approved`);
      state.set(submission, "revoked");
    } else if (kind === "submission.withdrawn") {
      if (now !== "submitted") problems.push(`log entry ${index} withdraws submission ${submission}, which was ${now}`);
      state.set(submission, "withdrawn");
    }
    const key = target.get(submission)!;
    if (!["submitted", "approved"].includes(state.get(submission)!) && active.get(key) === submission) active.delete(key);
    if (kind.startsWith("approval.")) {
      const kid = String(detail.key_id);
      const revokedAt = revokedKeys.get(kid);
      if (revokedAt !== undefined && revokedAt < index) {
        problems.push(`log entry ${index} is signed with key ${kid}, revoked in log entry ${revokedAt}: a revoked key's later signatures are refused`);
      }
      if (wanted && !wanted.has(index) && (scope == null || event.mission === scope)) {
        problems.push(`log entry ${index} records a signed decision (${kind}) but the bundle holds no envelope for it (its approvals row was removed?)`);
      }
    }
  });
  return [...problems, ...checkDuties(events), ...checkRoles(events)];
}
