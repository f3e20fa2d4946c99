import { plural } from "../format";

/** How many paths end at each terminal, as the paths tab and the review pages show it. */
export function PathCounts({
  count,
  byTerminal,
  testIdPrefix,
}: {
  count: number;
  byTerminal: Record<string, number>;
  testIdPrefix: string;
}) {
  return (
    <table className="counts">
      <caption>{plural(count, "path")} from the start goal to a terminal</caption>
      <thead>
        <tr>
          <th scope="col">Terminal</th>
          <th scope="col">Paths</th>
        </tr>
      </thead>
      <tbody>
        {Object.entries(byTerminal).map(([terminal, n]) => (
          <tr key={terminal}>
            <th scope="row">{terminal}</th>
            <td data-testid={`${testIdPrefix}${terminal}`}>{n.toLocaleString("en-US")}</td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}
