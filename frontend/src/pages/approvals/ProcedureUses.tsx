/**
 * The procedures a version's orders use: each library version by name, version and
 * pinned digest, whether the library holds it and who approved it, and one verdict line saying
 * whether every one is an approved version. Nothing is shown for orders that use none.
 */
import { ErrorMessage } from "../../components/Status";
import { shortDigest } from "../../format";
import { useProcedureUses } from "../../api/versions";

export function ProcedureUsesSection({ mission, version }: { mission: string; version: number }) {
  const { data, error } = useProcedureUses(mission, version);
  if (error) return <ErrorMessage error={error} />;
  if (!data || data.procedures.length === 0) return null;
  return (
    <section aria-labelledby="procedures-title" data-testid="review-procedures">
      <h2 id="procedures-title">Procedures</h2>
      <p className={data.all_approved ? "verdict ok" : "verdict bad"} data-testid="procedures-verdict">
        {data.all_approved
          ? "Every procedure these orders use is a version a supervisor approved."
          : "Not every procedure these orders use is an approved version."}
        {data.truncated && " (More procedures are named than are listed here.)"}
      </p>
      <table>
        <caption>Procedures used by {mission} v{version}</caption>
        <thead>
          <tr>
            <th scope="col">Procedure</th>
            <th scope="col">Version</th>
            <th scope="col">Pinned digest</th>
            <th scope="col">Approved by</th>
          </tr>
        </thead>
        <tbody>
          {data.procedures.map((use) => (
            <tr key={`${use.name}@${use.version}@${use.digest ?? ""}`} data-testid="procedure-use">
              <th scope="row">{use.name}</th>
              <td>{use.version}</td>
              <td>
                {use.digest ? <code title={use.digest}>{shortDigest(use.digest)}</code> : "none pinned"}
              </td>
              <td>{use.approved_by ?? (use.in_library ? "not approved" : "not in the library")}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </section>
  );
}
