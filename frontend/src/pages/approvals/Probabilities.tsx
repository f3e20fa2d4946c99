/** The review's outcome probabilities: what the supervisor signs with the orders. */
import { type OutcomeFigures, probabilityRows } from "./probabilities";

export function ProbabilityTable({ figures }: { figures: OutcomeFigures | null | undefined }) {
  if (!figures) return null;
  const rows = probabilityRows(figures);
  return (
    <>
      <h2>Outcome probabilities</h2>
      <p className="hint">
        {figures.exact
          ? "Exact, from the outcome probabilities in the orders; these figures are inside the signed statement."
          : `Bounds: ${[...figures.intervals, ...figures.unknown].join(", ")} give intervals or no probabilities.`}
      </p>
      <table data-testid="review-probabilities">
        <tbody>
          {rows.map((row) => (
            <tr key={row.what}>
              <th scope="row">{row.what}</th>
              <td>{row.value}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </>
  );
}
