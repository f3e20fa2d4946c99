/**
 * A team campaign's results: how many runs ended in each joint end (named as the verifier's
 * joint counts name them), beside how many joint executions the verifier counts there; the
 * meetings completed and deadlocked; each member's terminals; and the joint ends no run
 * reached. A run that ended where the verifier says no joint execution can is shown as a TEAM
 * finding. Every value is rendered as text.
 */
import { numberPair } from "../../api/pair";
import { type Schema } from "../../api/client";
import { type Column, DataTable } from "../../components/DataTable";
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

type Team = TeamResults["team"];

const JOINT_COLUMNS: Column<Team["joint"][number]>[] = [
  {
    header: "Joint end",
    rowHeader: true,
    cell: (row) =>
      jointParts(row.end).map(([vehicle, end]) => (
        <span key={vehicle} className="joint-part">
          {vehicle}: <span className={end === "waiting" ? "waiting" : undefined}>{end === "waiting" ? "left waiting" : end}</span>
        </span>
      )),
  },
  { header: "Runs", numeric: true, cell: (row) => row.count },
  { header: "Estimate", cell: (row) => <Interval e={row} /> },
  {
    header: "Verifier",
    cell: (row) =>
      row.possible === false ? "impossible (TEAM)" : row.executions === null ? "not counted" : `${row.executions} joint executions`,
  },
];

const MEETING_COLUMNS: Column<Team["meetings"][number]>[] = [
  { header: "Meeting", rowHeader: true, cell: (m) => m.meet },
  { header: "Vehicles", cell: (m) => m.vehicles.join(", ") },
  { header: "Completed", numeric: true, cell: (m) => m.completed.count },
  { header: "Deadlocked", numeric: true, cell: (m) => m.deadlocked.count },
  {
    header: "Shared outcomes",
    cell: (m) =>
      Object.entries(m.outcomes)
        .map(([o, n]) => `${o} ${n}`)
        .join(", "),
  },
];

const MEMBER_COLUMNS: Column<Team["members"][number]>[] = [
  { header: "Vehicle", rowHeader: true, cell: (m) => m.vehicle },
  {
    header: "Ends (runs)",
    cell: (m) =>
      Object.entries(m.terminals)
        .map(([t, e]) => `${t === "waiting" ? "left waiting" : t} ${e.count}`)
        .join(", "),
  },
  { header: "Own paths covered", cell: (m) => `${m.covered_paths} of ${m.total_paths ?? "?"}` },
];

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
        <DataTable
          caption="Joint ends: runs, estimate (95% Wilson interval), and the verifier's joint executions"
          showCaption
          className="team-joint"
          testId="joint-table"
          rows={team.joint}
          rowKey={(row) => row.end}
          rowClassName={(row) => (row.possible === false ? "impossible" : row.count === 0 ? "missed" : undefined)}
          columns={JOINT_COLUMNS}
        />
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
        <DataTable caption="Meetings" showCaption className="team-meetings" rows={team.meetings} rowKey={(m) => m.meet} columns={MEETING_COLUMNS} />
      </div>
      <div className="team-scroll">
        <DataTable caption="Each member's ends" showCaption className="team-members" rows={team.members} rowKey={(m) => m.vehicle} columns={MEMBER_COLUMNS} />
      </div>
    </section>
  );
}
