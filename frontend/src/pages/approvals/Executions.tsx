/**
 * What a record (approval) page shows of what vehicles did: each recorded execution
 * of the version, stated as "approved, executed as path 17, no deviation" or naming the
 * deviations, or "unverified" naming the times and readings it lacked; who uploaded each and
 * what it evidenced; and the cited rehearsal's runs checked by the same execution checker. All
 * text from the server is rendered as text.
 */
import type { Schema } from "../../api/client";
import { ErrorMessage, Loading } from "../../components/Status";
import { formatDateTime } from "../../format";
import { useRecordExecutions } from "../../api/approvals";
import { evidenceText } from "./evidence";

type Verdict = Schema<"ExecutionOut">;

function Deviations({ verdict }: { verdict: Pick<Verdict, "deviations"> }) {
  if (!verdict.deviations.length) return null;
  return (
    <ul className="checks">
      {verdict.deviations.map((d, i) => (
        <li key={i} className="check-bad">
          step {d.step} <strong>{d.code}</strong>: {d.message}
        </li>
      ))}
    </ul>
  );
}

export function ExecutionsSection({ approvalId }: { approvalId: number }) {
  const { data, error, isPending: loading } = useRecordExecutions(approvalId);
  if (loading && !data) return <Loading what="the executions" />;
  if (!data) return <ErrorMessage error={error ?? "The executions could not be loaded."} />;
  return (
    <>
      <h2>Executions</h2>
      {data.executions.length === 0 ? (
        <p data-testid="executions-none">No execution of this version has been recorded.</p>
      ) : (
        <ol data-testid="executions">
          {data.executions.map((e) => (
            <li key={e.log_index} data-testid="execution" className={e.ok ? "verdict ok" : "verdict bad"}>
              <span data-testid="execution-statement">{e.statement}</span>{" "}
              <span className="hint">
                (log entry {e.log_index}
                {e.actor ? `, uploaded by ${e.actor}` : ""}
                {e.at ? `, ${formatDateTime(e.at)}` : ""})
              </span>
              <div className="hint" data-testid="execution-evidence">
                {evidenceText(e.evidence)}
              </div>
            </li>
          ))}
        </ol>
      )}
      {data.rehearsal && (
        <>
          <h3>Rehearsal through the execution checker</h3>
          <ol data-testid="rehearsal-verdicts">
            {data.rehearsal.map((run, i) => (
              <li key={i} className={run.verdict.ok ? "verdict ok" : "verdict bad"}>
                <span data-testid="rehearsal-verdict">
                  {run.vehicle ? `${run.vehicle}: ` : ""}
                  {run.verdict.ok
                    ? `rehearsed as path ${run.verdict.path}, no deviation`
                    : `rehearsal run ${i + 1}: ${run.verdict.summary}`}
                </span>
                <Deviations verdict={run.verdict} />
              </li>
            ))}
          </ol>
        </>
      )}
    </>
  );
}
