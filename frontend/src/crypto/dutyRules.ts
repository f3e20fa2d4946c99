/**
 * Separation of duties by person as a log-wide rule, the browser's copy of
 * backend approvals/duty_rules.py (both run the vectors in __fixtures__/duties.json). Whoever
 * created the mission, edited its draft or cut a version up to the one decided, or submitted
 * it, may not decide it, whatever their role is now: the app refuses that, so such a decision
 * in the log was written behind its back. Pure: events in, problems out.
 */
export interface DutyEvent {
  kind?: string;
  actor?: unknown;
  mission?: unknown;
  detail?: Record<string, unknown>;
}

/** The event kinds that change a mission's content (store/decide_guard.py's list). */
export const EDIT_KINDS = new Set(["mission.created", "draft.updated", "version.created"]);
const DECIDING_KINDS = new Set(["approval.approved", "approval.rejected", "approval.revoked"]);

const keyOf = (mission: unknown, version: unknown): string => JSON.stringify([mission ?? null, version ?? null]);

/** One problem per decision whose actor authored, edited or cut the mission at or before the
 * entry that cut the decided version, or submitted the submission it decides. Without that
 * cut in the log, every edit before the decision counts (too many refused is safe). */
export function checkDuties(events: DutyEvent[]): string[] {
  const problems: string[] = [];
  const edits = new Map<string, { at: number; actor: unknown; kind: string }[]>();
  const cuts = new Map<string, number>();
  const submitted = new Map<unknown, { at: number; actor: unknown; mission: unknown; version: unknown }>();
  events.forEach((event, index) => {
    const kind = String(event.kind ?? "");
    const detail = event.detail ?? {};
    const { mission, actor } = event;
    if (EDIT_KINDS.has(kind) && mission != null) {
      const m = JSON.stringify(mission);
      if (!edits.has(m)) edits.set(m, []);
      edits.get(m)!.push({ at: index, actor, kind });
      const cut = keyOf(mission, detail.number);
      if (kind === "version.created" && !cuts.has(cut)) cuts.set(cut, index);
    } else if (kind === "submission.created") {
      if (!submitted.has(detail.submission)) submitted.set(detail.submission, { at: index, actor, mission, version: detail.version });
    } else if (DECIDING_KINDS.has(kind) && actor != null) {
      const sub = submitted.get(detail.submission);
      if (!sub) return; // checkLog names a decision on a submission the log never created
      const cut = cuts.get(keyOf(sub.mission, sub.version)) ?? index;
      const why = (edits.get(JSON.stringify(sub.mission)) ?? []).filter((e) => e.actor === actor && e.at <= cut).map((e) => ({ at: e.at, kind: e.kind }));
      if (sub.actor === actor) why.push({ at: sub.at, kind: "submission.created" });
      if (why.length === 0) return;
      why.sort((a, b) => a.at - b.at);
      const first = why[0]!;
      const verb = first.kind === "submission.created" ? "submitted" : "edited";
      problems.push(
        `log entry ${index} (${kind}) by ${String(actor)} decides submission ${String(detail.submission)} of ${String(sub.mission)} version ${String(sub.version)}, but ${String(actor)} ${verb} it in log entry ${first.at} (${first.kind}): separation of duties`,
      );
    }
  });
  return problems;
}
