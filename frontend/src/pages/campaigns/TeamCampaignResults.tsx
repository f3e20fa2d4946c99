/**
 * A team campaign's results: how many runs ended in each joint end (named as the verifier's
 * joint counts name them), beside how many joint executions the verifier counts there; the
 * meetings completed and deadlocked; each member's terminals; and the joint ends no run
 * reached. A run that ended where the verifier says no joint execution can is shown as a TEAM
 * finding. Every value is rendered as text.
 */
import { numberPair } from "../../api/pair";
import { type Schema } from "../../api/client";
import "./teamCampaign.css";

type TeamResults = Schema<"TeamCampaignResults">;
type Estimate = Schema<"Estimate">;

const percent = (x: number | null) => (x === null || !Number.isFinite(x) ? "—" : `${(100 * x).toFixed(1)}%`);

/** `remus-100:waiting + vehicle-2:ABORT` as [vehicle, end] pairs (ends hold no colon). */
export function jointParts(end: string): [string, string][] {
  return end.split(" + ").map((part) => {
    const at = part.lastIndexOf(":");
    return at < 0 ? [part, ""] : [part.slice(0, at), part.slice(at + 1)];
  });
}

function Interval({ e }: { e: Estimate }) {
  const [low, high] = numberPair(e.ci);
  return (
    <>
      {percent(e.p)}{" "}
      <span className="team-ci">
        ({percent(low)} – {percent(high)})
      </span>
    </>
  );
}

export function TeamCampaignResults({ id, results }: { id: string; results: TeamResults }) {
  const team = results.team;
  const coverage = team.coverage;
  return (
    <section aria-labelledby="campaign-results-title" className="campaign-results team-campaign">
      <h4 id="campaign-results-title">
        Campaign <code>{id}</code>: {results.simulations} simulations of a team ({team.vehicles.join(", ")})
      </h4>
      {team.findings.length > 0 && (
        <ul className="team-findings" aria-label="Findings">
          {team.findings.map((f) => (
            <li key={f.end}>
              <strong>{f.code}</strong> {f.message}
            </li>
          ))}
        </ul>
      )}
      <div className="team-scroll">
        <table className="team-joint" data-testid="joint-table">
          <caption>Joint ends: runs, estimate (95% Wilson interval), and the verifier's joint executions</caption>
          <thead>
            <tr>
              <th scope="col">Joint end</th>
              <th scope="col">Runs</th>
              <th scope="col">Estimate</th>
              <th scope="col">Verifier</th>
            </tr>
          </thead>
          <tbody>
            {team.joint.map((row) => (
              <tr key={row.end} className={row.possible === false ? "impossible" : row.count === 0 ? "missed" : undefined}>
                <th scope="row">
                  {jointParts(row.end).map(([vehicle, end]) => (
                    <span key={vehicle} className="joint-part">
                      {vehicle}: <span className={end === "waiting" ? "waiting" : undefined}>{end === "waiting" ? "left waiting" : end}</span>
                    </span>
                  ))}
                </th>
                <td>{row.count}</td>
                <td>
                  <Interval e={row} />
                </td>
                <td>
                  {row.possible === false
                    ? "impossible (TEAM)"
                    : row.executions === null
                      ? "not counted"
                      : `${row.executions} joint executions`}
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      </div>
      {team.unfinished.count > 0 && (
        <p>{team.unfinished.count} runs were stopped by a bound before every member ended; they have no joint end.</p>
      )}
      <p data-testid="joint-coverage">
        {coverage.checked
          ? `Joint ends reached: ${coverage.reached} of ${coverage.possible ?? "?"} the verifier counts.`
          : "The verifier could not count the joint executions, so no run is held against them."}
        {coverage.missed.length > 0 && ` Never reached: ${coverage.missed.join("; ")}. The campaign says nothing about these.`}
      </p>
      <div className="team-scroll">
        <table className="team-meetings">
          <caption>Meetings</caption>
          <thead>
            <tr>
              <th scope="col">Meeting</th>
              <th scope="col">Vehicles</th>
              <th scope="col">Completed</th>
              <th scope="col">Deadlocked</th>
              <th scope="col">Shared outcomes</th>
            </tr>
          </thead>
          <tbody>
            {team.meetings.map((m) => (
              <tr key={m.meet}>
                <th scope="row">{m.meet}</th>
                <td>{m.vehicles.join(", ")}</td>
                <td>{m.completed.count}</td>
                <td>{m.deadlocked.count}</td>
                <td>
                  {Object.entries(m.outcomes)
                    .map(([o, n]) => `${o} ${n}`)
                    .join(", ")}
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      </div>
      <div className="team-scroll">
        <table className="team-members">
          <caption>Each member's ends</caption>
          <thead>
            <tr>
              <th scope="col">Vehicle</th>
              <th scope="col">Ends (runs)</th>
              <th scope="col">Own paths covered</th>
            </tr>
          </thead>
          <tbody>
            {team.members.map((m) => (
              <tr key={m.vehicle}>
                <th scope="row">{m.vehicle}</th>
                <td>
                  {Object.entries(m.terminals)
                    .map(([t, e]) => `${t === "waiting" ? "left waiting" : t} ${e.count}`)
                    .join(", ")}
                </td>
                <td>
                  {m.covered_paths} of {m.total_paths ?? "?"}
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      </div>
    </section>
  );
}
