/**
 * Rehearsal campaigns on the mission page's Versions tab: start N seeded
 * simulations of a version over a sweep of faults and injection goals, follow the progress,
 * cancel, and read the estimates: terminal probabilities with 95% Wilson intervals, the paths
 * covered (numbered as in the Paths tab), an energy histogram, and per-goal outcome
 * probabilities offered for the orders' `p` (copied by the operator, never written for them).
 * A team's campaign shows its joint table instead (TeamCampaignResults.tsx).
 */
import { useState } from "react";

import { api, type Schema, unwrap } from "../../api/client";
import { numberPair } from "../../api/pair";
import { type Column, DataTable } from "../../components/DataTable";
import { ErrorMessage, Notice } from "../../components/Status";
import { useCan, useSession } from "../../session";
import { useCancelCampaign, useFaultReach, useMissionCampaigns, useStartCampaign } from "../../api/campaigns";
import { TeamCampaignResults } from "./TeamCampaignResults";

type Campaign = Schema<"CampaignOut">;
const anyRunning = (campaigns: Campaign[]) => campaigns.some((c) => ACTIVE.has(c.state));
type Estimate = Schema<"Estimate">;

const FAULTS = ["none", "gps_loss", "nav_drift", "leak", "low_energy", "contact_close"];
const ACTIVE = new Set(["queued", "running"]);

export function CampaignPanel({ mission, versions }: { mission: string; versions: number[] }) {
  const canStart = useCan("startCampaign");
  // Asked again every second while a campaign is queued or running (its progress).
  const { data, error } = useMissionCampaigns(mission, { pollWhile: anyRunning });
  const campaigns = data ?? [];
  const [shown, setShown] = useState<string | null>(null);
  const selected = campaigns.find((c) => c.id === shown && c.results);
  return (
    <section aria-labelledby="campaigns-title" className="card">
      <h3 id="campaigns-title">Rehearsal campaigns</h3>
      <p className="hint">
        Many seeded simulations of a version; the results estimate how likely each ending is.
      </p>
      <ErrorMessage error={error} />
      {canStart && versions.length > 0 && <StartForm mission={mission} versions={versions} />}
      {campaigns.length > 0 && (
        <DataTable
          caption="Campaigns, newest first"
          className="campaigns"
          rows={campaigns}
          rowKey={(c) => c.id}
          columns={campaignColumns(mission, (c) => setShown(c.id))}
        />
      )}
      {selected && <CampaignResults campaign={selected} />}
    </section>
  );
}

function StartForm({ mission, versions }: { mission: string; versions: number[] }) {
  const [version, setVersion] = useState(Math.max(...versions));
  const [simulations, setSimulations] = useState(100);
  const [faults, setFaults] = useState<string[]>(["none"]);
  const [goals, setGoals] = useState("start");
  // A team's faults for one member (`vehicle-2:leak`), beside the ones every member gets.
  const [memberFaults, setMemberFaults] = useState("");
  const [seed, setSeed] = useState(0);
  const startCampaign = useStartCampaign(mission);
  const busy = startCampaign.isPending;
  const perMember = memberFaults.split(",").map((f) => f.trim()).filter(Boolean);
  const sweep = [...faults, ...perMember];
  const start = () =>
    startCampaign.mutate({
      version,
      body: { simulations, faults: sweep, goals: goals.split(",").map((g) => g.trim()).filter(Boolean), seed },
    });
  const toggle = (fault: string) =>
    setFaults((f) => (f.includes(fault) ? f.filter((x) => x !== fault) : [...f, fault]));
  // Before the run: which chosen faults nothing in the version reacts to.
  const chosen = sweep.filter((f) => f !== "none");
  const reach = useFaultReach(mission, version, chosen);
  const idle = (reach.data ?? []).filter((r) => !r.reacts);
  return (
    <fieldset className="campaign-form">
      <legend>New campaign</legend>
      <label>
        Version{" "}
        <select value={version} onChange={(e) => setVersion(Number(e.target.value))}>
          {versions.map((v) => (
            <option key={v} value={v}>
              v{v}
            </option>
          ))}
        </select>
      </label>{" "}
      <label>
        Simulations{" "}
        <input type="number" min={1} max={10000} value={simulations} onChange={(e) => setSimulations(Number(e.target.value))} />
      </label>{" "}
      <label>
        First seed <input type="number" min={0} value={seed} onChange={(e) => setSeed(Number(e.target.value))} />
      </label>
      <div role="group" aria-label="Faults of the sweep">
        {FAULTS.map((fault) => (
          <label key={fault}>
            <input type="checkbox" checked={faults.includes(fault)} onChange={() => toggle(fault)} /> {fault}
          </label>
        ))}
      </div>
      <div>
        <label>
          One team member's faults (VEHICLE:FAULT, comma separated){" "}
          <input value={memberFaults} maxLength={400} placeholder="vehicle-2:leak" onChange={(e) => setMemberFaults(e.target.value)} />
        </label>
      </div>
      <label>
        Inject at (goals, comma separated; start = from the start){" "}
        <input value={goals} maxLength={400} onChange={(e) => setGoals(e.target.value)} />
      </label>{" "}
      {idle.length > 0 && (
        <ul className="fault-reach" data-testid="idle-faults">
          {idle.map((r) => (
            <li key={r.fault}>
              {r.because}: a campaign of it only repeats the runs without it.
            </li>
          ))}
        </ul>
      )}
      <button type="button" className="primary" onClick={start} disabled={busy || sweep.length === 0}>
        {busy ? "Starting…" : "Start campaign"}
      </button>
      <ErrorMessage error={startCampaign.error} />
    </fieldset>
  );
}

/** A campaign a row: its id, version, sweep, progress and state, then its buttons. */
function campaignColumns(mission: string, onShow: (c: Campaign) => void): Column<Campaign>[] {
  return [
    { header: "Campaign", cell: (c) => <code>{c.id}</code> },
    { header: "Version", cell: (c) => `v${c.version}` },
    { header: "Sweep", cell: (c) => `${c.spec.faults.join(", ")} at ${c.spec.goals.join(", ")}; seeds from ${c.spec.seed}` },
    {
      header: "Progress",
      cell: (c) => (
        <span className="campaign-progress">
          <progress max={c.simulations} value={c.done} aria-label={`Campaign ${c.id} progress`} /> {c.done} / {c.simulations}
        </span>
      ),
    },
    {
      header: "State",
      cell: (c) => (
        <>
          {c.state}
          {c.error && <span className="error"> {c.error}</span>}
        </>
      ),
    },
    { header: "Actions", hiddenHeader: true, cell: (c) => <CampaignActions mission={mission} campaign={c} onShow={() => onShow(c)} /> },
  ];
}

/** Cancel (its owner, while it runs) and Results (once it has them). */
function CampaignActions({ mission, campaign: c, onShow }: { mission: string; campaign: Campaign; onShow: () => void }) {
  const { user } = useSession();
  const canCancel = useCan("cancelCampaign") && c.owner === user?.username && ACTIVE.has(c.state);
  const cancelCampaign = useCancelCampaign(mission);
  const cancel = () => cancelCampaign.mutate(c.id);
  return (
    <>
      {canCancel && (
        <button type="button" onClick={cancel} disabled={cancelCampaign.isPending}>
          Cancel
        </button>
      )}
      {c.results && (
        <button type="button" onClick={onShow}>
          Results
        </button>
      )}
      <ErrorMessage error={cancelCampaign.error} />
    </>
  );
}

/** A proportion as a percentage; "—" when there is none (no estimate, or a bound missing). */
export const percent = (x: number | null) => (x === null || !Number.isFinite(x) ? "—" : `${(100 * x).toFixed(1)}%`);

const ESTIMATE_COLUMNS: Column<[string, Estimate]>[] = [
  { header: "Ending", rowHeader: true, cell: ([ending]) => ending },
  { header: "Estimate", numeric: true, cell: ([, e]) => percent(e.p) },
  {
    header: "Interval",
    cell: ([, e]) => {
      const [low, high] = numberPair(e.ci);
      return `${percent(low)} – ${percent(high)}`;
    },
  },
  { header: "Simulations", numeric: true, cell: ([, e]) => e.count },
];

/** A finished campaign's estimates; `offer` adds the button that offers per-goal probabilities. */
export function CampaignResults({ campaign, offer: offering = true }: { campaign: Campaign; offer?: boolean }) {
  const results = campaign.results;
  const [offered, setOffered] = useState<string | null>(null);
  const offer = async () => {
    const body = unwrap(
      await api.GET("/api/campaigns/{campaign_id}/probabilities", { params: { path: { campaign_id: campaign.id } } }),
    );
    const p = Object.fromEntries(Object.entries(body.goals).map(([goal, g]) => [goal, { p: g.point }]));
    setOffered(JSON.stringify(p, null, 2));
  };
  if (!results) return <p>This campaign has no results yet.</p>;
  if ("team" in results) return <TeamCampaignResults id={campaign.id} results={results} />;
  const coverage = results.coverage;
  return (
    <section aria-labelledby="campaign-results-title" className="campaign-results">
      <h4 id="campaign-results-title">
        Campaign <code>{campaign.id}</code>: {results.simulations} simulations
      </h4>
      <DataTable
        caption="Estimated probabilities (95% Wilson intervals)"
        showCaption
        rows={Object.entries(results.terminals)}
        footer={[["Any violation", results.any_violation]]}
        rowKey={([ending]) => ending}
        columns={ESTIMATE_COLUMNS}
      />
      <p data-testid="campaign-covered">
        Paths covered: {coverage.covered} of {coverage.total_paths ?? "?"}
        {coverage.paths.length > 0 && ": "}
        {coverage.paths.map((p) => `#${p.path} (${p.count})`).join(", ")}
      </p>
      <NotReached covered={coverage.paths.map((p) => p.path)} total={coverage.total_paths ?? null} />
      <EnergyHistogram edges={results.energy_wh.histogram.edges} counts={results.energy_wh.histogram.counts} />
      {offering &&
        (coverage.covered > 1 ? (
          <button type="button" onClick={offer}>
            Offer per-goal probabilities
          </button>
        ) : (
          <p className="hint" data-testid="no-offer">
            No per-goal probabilities are offered: every run took the same path, so each goal it reached shows one
            outcome with certainty, which says nothing about the others. Add faults that something reacts to, or more
            injection goals.
          </p>
        ))}
      {offered && (
        <>
          <Notice>
            Estimated outcome probabilities per goal, in the orders’ form. Copy them into the draft yourself if you want
            them; nothing was changed.
          </Notice>
          <pre className="offered-p">{offered}</pre>
        </>
      )}
    </section>
  );
}

/** The paths no simulation took, by number as in Paths: the first 40, then how many more. */
export function notReached(covered: number[], total: number | null, shown = 40): { first: number[]; more: number } | null {
  if (total === null || !Number.isSafeInteger(total) || total <= 0) return null;
  const taken = new Set(covered);
  const first: number[] = [];
  let missing = total - taken.size;
  for (let n = 1; n <= total && first.length < shown; n++) if (!taken.has(n)) first.push(n);
  missing = Math.max(0, missing - first.length);
  return { first, more: missing };
}

function NotReached({ covered, total }: { covered: number[]; total: number | null }) {
  const missing = notReached(covered, total);
  if (!missing || missing.first.length === 0) return null;
  return (
    <p data-testid="campaign-not-reached">
      Not reached: {missing.first.map((n) => `#${n}`).join(", ")}
      {missing.more > 0 && `, and ${missing.more.toLocaleString("en-US")} more`}. The campaign says nothing about
      these paths.
    </p>
  );
}

export function EnergyHistogram({ edges, counts }: { edges: number[]; counts: number[] }) {
  const width = 480;
  const height = 160;
  const pad = 28;
  const peak = Math.max(1, ...counts);
  const barWidth = counts.length ? (width - 2 * pad) / counts.length : 0;
  return (
    <figure>
      <svg viewBox={`0 0 ${width} ${height}`} width={width} height={height} role="img" aria-label="Energy used per simulation, histogram">
        <line x1={pad} y1={height - pad} x2={width - pad} y2={height - pad} stroke="currentColor" />
        {counts.map((count, i) => {
          const h = ((height - 2 * pad) * count) / peak;
          return (
            <rect key={i} x={pad + i * barWidth + 1} y={height - pad - h} width={Math.max(1, barWidth - 2)} height={h} fill="steelblue">
              <title>{`${edges[i]?.toFixed(0)}–${edges[i + 1]?.toFixed(0)} Wh: ${count}`}</title>
            </rect>
          );
        })}
        {edges.length > 0 && (
          <>
            <text x={pad} y={height - 8} fontSize="11">
              {(edges[0] ?? 0).toFixed(0)} Wh
            </text>
            <text x={width - pad} y={height - 8} fontSize="11" textAnchor="end">
              {(edges[edges.length - 1] ?? 0).toFixed(0)} Wh
            </text>
            <text x={pad} y={pad - 8} fontSize="11">
              {peak}
            </text>
          </>
        )}
      </svg>
      <figcaption>Energy used per simulation (Wh)</figcaption>
    </figure>
  );
}
