import type { Finding } from "../api/client";

/** The findings of a validation report, as the findings tab and the review pages list them. */
export function FindingsTable({ findings, caption }: { findings: Finding[]; caption: string }) {
  if (findings.length === 0) return <p className="empty">No findings.</p>;
  return (
    <div className="table-wrap">
      <table className="findings">
        <caption className="visually-hidden">{caption}</caption>
        <thead>
          <tr>
            <th scope="col">Code</th>
            <th scope="col">Severity</th>
            <th scope="col">Subjects</th>
            <th scope="col">Message</th>
          </tr>
        </thead>
        <tbody>
          {findings.map((f, i) => (
            <tr key={`${f.code}-${i}`} className={`severity-${f.severity}`}>
              <td>
                <code>{f.code}</code>
              </td>
              <td>
                <span className={`badge ${f.severity === "error" ? "bad" : "warn"}`}>{f.severity}</span>
              </td>
              <td>{f.subjects.join(", ")}</td>
              <td>{f.message}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
