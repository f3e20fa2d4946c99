/**
 * A rehearsal record as a short table: how it ended, the path it took step by
 * step (goal id and outcome letter, titles in the tooltip), simulated time, energy, by whom, and
 * links to the standalone replay and the record itself. The review loads the record the
 * submission cites by its digest; the record page passes the one the approval carries. Every
 * value is rendered as text.
 */
import type { ReactNode } from "react";

import type { Schema } from "../../api/client";
import { DataTable } from "../../components/DataTable";
import { ErrorMessage, Loading } from "../../components/Status";
import { formatDateTime, shortDigest } from "../../format";
import { OUTCOME_LETTERS, OUTCOME_WORDS } from "../../pathGrid";
import { useRehearsalRecord } from "../../api/rehearsals";
import { duration } from "./probabilities";
import "./review.css";

/** What the summary reads: a stored record (RecordDetail) or the one an approval cites. */
type RecordDetail = Pick<Schema<"RecordDetail">, "digest" | "version" | "source" | "owner" | "created_at" | "replay" | "record">;
type Run = Schema<"RecordRun">;
type RecordBody = RecordDetail["record"];

/** The record's runs as rows: one vehicle's, or each team member's labelled with its vehicle
 * (a team's record has no single run of its own), and how it ended. */
export function summaryRows(record: RecordBody): { ended: string; rows: { label: string; run: Run }[] } {
  if (record.team) {
    const rows = record.team.members.flatMap((m) =>
      m.runs.map((run, i) => ({ label: m.runs.length > 1 ? `${m.vehicle}, run ${i + 1}` : m.vehicle, run })),
    );
    return { ended: `the joint end ${record.team.joint_end}`, rows };
  }
  const runs = record.runs.length > 0 ? record.runs : [{ path_index: null, goals: record.goals, outcomes: record.outcomes, terminal: record.terminal, terminal_kind: record.terminal_kind }];
  const ended = record.terminal
    ? `${record.terminal}${record.terminal_kind ? ` (${record.terminal_kind})` : ""}`
    : "did not reach a terminal";
  return { ended, rows: runs.map((run, i) => ({ label: runs.length > 1 ? `Run ${i + 1}` : "Path", run })) };
}

const SOURCE: Record<string, string> = {
  manual: "outcomes chosen step by step",
  replay: "a traversal path replayed",
  tour: "a tour of the paths",
  simulate: "outcomes decided by the simulation",
};

export function recordHref(digest: string): string {
  return `/api/rehearsal-records/${encodeURIComponent(digest)}`;
}

/** The cited record, fetched by digest (the review: the submission names only the digest). */
export function CitedRehearsal({ digest, titles }: { digest: string; titles: ReadonlyMap<string, string> }) {
  const { data, error, isPending: loading } = useRehearsalRecord(digest);
  if (loading && !data) return <Loading what="the cited rehearsal" />;
  if (!data) return <ErrorMessage error={error ?? "The cited rehearsal record could not be loaded."} />;
  return <RehearsalSummary detail={data} titles={titles} />;
}

function Steps({ run, titles }: { run: Run; titles: ReadonlyMap<string, string> }) {
  return (
    <ol className="rehearsal-steps" data-testid="rehearsal-steps">
      {run.goals.map((goal, i) => {
        const outcome = run.outcomes[i] ?? "";
        const title = titles.get(goal);
        return (
          <li key={i} title={`${goal}${title ? `: ${title}` : ""} — ${OUTCOME_WORDS[outcome] ?? (outcome || "not decided")}`}>
            <code>{goal}</code>{" "}
            <span className={`outcome-letter outcome-${outcome}`}>{OUTCOME_LETTERS[outcome] ?? "–"}</span>
          </li>
        );
      })}
      <li>
        → <strong>{run.terminal ?? "not finished"}</strong>
      </li>
    </ol>
  );
}

interface Field {
  label: ReactNode;
  value: ReactNode;
  testId?: string;
}

/** The record's fields in the order a reader asks: how it ended, the path(s), what was
 * rehearsed, what the simulation used, who and when, and where the record itself is. */
function fields(detail: RecordDetail, titles: ReadonlyMap<string, string>): Field[] {
  const record = detail.record;
  const { ended, rows } = summaryRows(record);
  return [
    {
      label: "Outcome",
      value: record.state === "stopped_early" ? `Stopped early; ${ended}` : `Ended at ${ended}`,
      testId: "rehearsal-outcome",
    },
    ...rows.map(({ label, run }) => ({
      label: `${label}${run.path_index ? ` #${run.path_index}` : ""}`,
      value: <Steps run={run} titles={titles} />,
    })),
    {
      label: "Rehearsed",
      value: (
        <>
          {detail.version !== null ? `v${detail.version}` : "the draft"}, {SOURCE[detail.source] ?? detail.source}, seed {record.seed}
          {record.options.faults.length > 0 && `, faults: ${record.options.faults.join(", ")}`}
        </>
      ),
    },
    {
      label: "Simulated",
      value: (
        <>
          {duration(record.sim_time_s)}, {record.energy.used_wh.toLocaleString("en-US", { maximumFractionDigits: 1 })} Wh of{" "}
          {record.energy.capacity_wh.toLocaleString("en-US", { maximumFractionDigits: 0 })} Wh used
        </>
      ),
    },
    {
      label: "By, when",
      value: (
        <>
          {detail.owner ?? "?"}, <time dateTime={String(detail.created_at)}>{formatDateTime(String(detail.created_at))}</time>
        </>
      ),
    },
    {
      label: "Record",
      value: (
        <>
          <code title={detail.digest}>{shortDigest(detail.digest, 16)}</code> ·{" "}
          <a href={detail.replay} target="_blank" rel="noreferrer" data-testid="rehearsal-replay">
            Replay in 3D
          </a>{" "}
          · <a href={recordHref(detail.digest)}>Record (JSON)</a>
        </>
      ),
    },
  ];
}

export function RehearsalSummary({ detail, titles }: { detail: RecordDetail; titles: ReadonlyMap<string, string> }) {
  return (
    <DataTable
      caption={`Rehearsal record ${shortDigest(detail.digest, 12)}`}
      className="rehearsal-summary"
      testId="rehearsal-summary"
      columnHeaders={false}
      rows={fields(detail, titles)}
      rowKey={(_, i) => i}
      columns={[
        { header: "Field", rowHeader: true, cell: (f) => f.label },
        { header: "Value", cell: (f) => f.value, testId: (f) => f.testId },
      ]}
    />
  );
}
