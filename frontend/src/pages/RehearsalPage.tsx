/**
 * The rehearsal view: start a rehearsal of the draft or a version, watch it in viser
 * (served by the app at /rehearsal/{id}/, its websocket proxied after the session check) beside
 * the mission graph with the current goal highlighted, choose outcomes, inject faults, stop it
 * into a stored record, and open the records' standalone replays.
 */
import { useCallback, useEffect, useRef, useState } from "react";

import { api, ApiError, type MissionDetail, type paths } from "../api/client";
import { ErrorMessage, Loading, Notice } from "../components/Status";
import { goals, OUTCOME_LABEL, OUTCOMES, type Orders, type Outcome, successors, terminals } from "../editor/graph";
import { type MemberSpec, teamOf } from "../editor/scope";
import { formatDateTime, shortDigest } from "../format";
import { useRehearsalCommand, useRehearsalRecords, useStopRehearsal } from "../api/rehearsals";
import { RefinedGoalCard } from "./RefinedGoalCard";
import { type MemberPaths, TeamMemberSources } from "./rehearsal/TeamMemberSources";
import { outcomeKey, pathOrder, stepPlace } from "./rehearsalOrder";
import "./rehearsal.css";

type JsonBody<R> = R extends { content: { "application/json": infer T } } ? T : never;
type Started = JsonBody<paths["/api/missions/{mission_id}/rehearsals"]["post"]["responses"][201]>;
type Status = Started["status"];
type Source = Status["source"];
type TeamStatus = NonNullable<Status["team"]>;
type MemberStatus = TeamStatus["members"][number];

const SOURCES: { value: Source; label: string }[] = [
  { value: "manual", label: "Chosen step by step" },
  { value: "replay", label: "Replay one traversal path" },
  { value: "tour", label: "Tour of all paths" },
  { value: "simulate", label: "Decided by the simulation" },
];
const FAULTS: { value: string; label: string }[] = [
  { value: "gps_loss", label: "GPS loss" },
  { value: "nav_drift", label: "Navigation drift" },
  { value: "leak", label: "Leak" },
  { value: "low_energy", label: "Low energy" },
  { value: "contact_close", label: "Contact closing inside 1,000 m" },
];
const STATE_LABEL: Record<Status["state"], string> = {
  running: "Running",
  waiting_for_outcome: "Waiting for the outcome",
  finished: "Finished",
  stopped: "Stopped (idle); stop it to record it",
};
const POLL_MS = 1000;
const KEY_OF: Record<Outcome, string> = { succeed: "s", fail: "f", violate: "c" };

const FAULT_LABEL: Record<string, string> = Object.fromEntries(FAULTS.map((f) => [f.value, f.label]));
// The team scene's vehicle colours (rehearse/team_scene.py VEHICLE_COLOURS), in team order.
const VEHICLE_COLOURS = ["#fac81e", "#28c8e6", "#e65ac8", "#ff8c3c", "#966efa", "#78e678", "#fafafa", "#3c6efa"];
const MEMBER_STATE: Record<MemberStatus["state"], string> = {
  running: "running",
  waiting: "holding at a meeting",
  finished: "ended",
  deadlocked: "left waiting (deadlock)",
};
/** A fault as the team's status names it (`vehicle-2:leak`) in words. */
function faultWords(fault: string): string {
  const at = fault.indexOf(":");
  if (at < 0) return FAULT_LABEL[fault] ?? fault;
  const name = fault.slice(at + 1);
  return `${fault.slice(0, at)}: ${FAULT_LABEL[name] ?? name}`;
}

/** Simulated time as "5 h 04 min 19 s" (never a bare 0h00m for a rehearsal that ran). */
export function simulatedTime(seconds: number): string {
  const s = Math.max(0, Math.round(seconds));
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  const rest = s % 60;
  if (h > 0) return `${h} h ${String(m).padStart(2, "0")} min ${String(rest).padStart(2, "0")} s`;
  if (m > 0) return `${m} min ${String(rest).padStart(2, "0")} s`;
  return `${rest} s`;
}

export function RehearsalPanel({ mission, canRehearse }: { mission: MissionDetail; canRehearse: boolean }) {
  const [live, setLive] = useState<Started | null>(null);
  const [error, setError] = useState<unknown>(null);
  const command = useRehearsalCommand(mission.id);
  const stop = useStopRehearsal(mission.id);
  const busy = command.isPending || stop.isPending;
  // A team's orders: every vehicle in one scene; the switcher picks the vehicle whose
  // goal cards are shown and into which the fault buttons inject.
  const team = teamOf(mission.orders);
  const [memberIndex, setMemberIndex] = useState(0);
  const member: MemberSpec | null = team ? (team[Math.min(memberIndex, team.length - 1)] ?? null) : null;
  const records = useRehearsalRecords(mission.id, null);

  // Poll the live rehearsal's status while it runs.
  const liveId = live?.id;
  useEffect(() => {
    if (!liveId) return;
    let stopped = false;
    const timer = window.setInterval(() => {
      void api.GET("/api/rehearsals/{rehearsal_id}", { params: { path: { rehearsal_id: liveId } } }).then(
        ({ data, response }) => {
          if (stopped) return;
          if (data) setLive(data);
          else if (response.status === 404 || response.status === 410) {
            setLive(null);
            setError("The rehearsal has ended (stopped elsewhere or idle too long).");
          }
        },
        () => undefined,
      );
    }, POLL_MS);
    return () => {
      stopped = true;
      window.clearInterval(timer);
    };
  }, [liveId]);

  const act = useCallback(async (work: () => Promise<void>) => {
    setError(null);
    try {
      await work();
    } catch (e) {
      setError(e);
    }
  }, []);
  const { mutateAsync: send } = command;

  const status: Status | undefined = live?.status;
  const state = status?.state ?? null;
  const teamStatus = status?.team ?? null;
  const memberStatus = member && teamStatus ? (teamStatus.members.find((m) => m.vehicle === member.vehicle) ?? null) : null;
  const current = (teamStatus ? memberStatus?.current_goal : status?.current_goal) ?? null;
  const currentGoal = current?.id ?? null;
  const finished = state === "finished" || state === "stopped";
  const waiting = state === "waiting_for_outcome";
  const question = status?.question ?? null;
  const terminal = status?.terminal ?? null;
  const simTime = status?.sim_time_s ?? null;
  const energyLeft = status?.energy_wh ?? null;
  const energyUsed = status?.energy_used_wh ?? null;
  const capacity = status?.capacity_wh ?? null;
  const activeFaults = status?.faults ?? [];
  const queuedFaults = status?.queued_faults ?? [];
  const suggested = status?.suggested;
  const [faultNotice, setFaultNotice] = useState<string | null>(null);
  // A notice about a fault ("Fault queued for the next goal") means nothing once the mission has
  // ended: clear it then, instead of leaving it beside "Finished".
  const ended = finished || terminal !== null;
  useEffect(() => {
    if (ended) setFaultNotice(null);
  }, [ended]);

  const choose = useCallback(
    (outcome: Outcome) => {
      if (!live) return;
      void act(async () => setLive(await send({ rehearsal: live.id, outcome })));
    },
    [live, act, send],
  );
  // The prompt's answers from the keyboard: s, f, c (Figure 6), unless the key is typed into a
  // field or carries a modifier (Ctrl+F stays the browser's find).
  const answering = live?.source === "manual" && waiting && !busy;
  useEffect(() => {
    if (!answering) return;
    const onKey = (event: KeyboardEvent) => {
      if (event.ctrlKey || event.metaKey || event.altKey || event.repeat) return;
      const target = event.target as HTMLElement | null;
      if (target && (target.isContentEditable || ["INPUT", "TEXTAREA", "SELECT"].includes(target.tagName))) return;
      const outcome = outcomeKey(event.key);
      if (outcome === null) return;
      event.preventDefault();
      choose(outcome);
    };
    document.addEventListener("keydown", onKey);
    return () => document.removeEventListener("keydown", onKey);
  }, [answering, choose]);

  // Bring the 3D view and its controls into view together when a rehearsal starts.
  const view = useRef<HTMLDivElement>(null);
  useEffect(() => {
    if (liveId) view.current?.scrollIntoView({ block: "start" });
  }, [liveId]);

  return (
    <>
      <h2>Rehearsal</h2>
      <ErrorMessage error={error} />
      {!live && canRehearse && (
        <StartForm
          mission={mission}
          team={team !== null}
          vehicles={team?.map((m) => m.vehicle) ?? []}
          busy={busy}
          onStart={(body) => act(async () => setLive(await send({ start: body })))}
        />
      )}
      {!live && !canRehearse && <Notice>Your role may read rehearsal records but not rehearse.</Notice>}
      {live && (
        <div className="rehearsal rehearsal-layout" data-testid="rehearsal" ref={view}>
          <div className="rehearsal-controls">
            <p role="status" aria-live="polite" data-testid="rehearsal-status">
              <strong data-testid="rehearsal-state">{state ? STATE_LABEL[state] : "Starting"}</strong>
              {current ? (
                <>
                  {" "}
                  · goal <span data-testid="current-goal">{current.title || current.id}</span>
                  {` (${Math.round(current.progress * 100)}%)`}
                </>
              ) : null}
              {terminal ? ` · ended at ${terminal}` : null}
              {" "}· step <span data-testid="rehearsal-step">{String(live.status.step)}</span>
            </p>
            {status?.refined && <RefinedGoalCard refined={status.refined} current={status.current_goal} />}
            <dl className="rehearsal-figures" data-testid="rehearsal-figures">
              <dt>Simulated time</dt>
              <dd data-testid="rehearsal-time">{simTime === null ? "—" : simulatedTime(simTime)}</dd>
              <dt>Energy</dt>
              <dd data-testid="rehearsal-energy">
                {energyLeft === null
                  ? "—"
                  : `${energyLeft.toFixed(0)} Wh left of ${capacity?.toFixed(0) ?? "?"} Wh (${energyUsed?.toFixed(1) ?? "?"} Wh used)`}
              </dd>
              <dt>Faults</dt>
              <dd data-testid="rehearsal-faults">
                {activeFaults.length ? activeFaults.map(faultWords).join(", ") : "none"}
                {queuedFaults.length && !ended
                  ? ` · queued for the next goal: ${queuedFaults.map((f) => FAULT_LABEL[f] ?? f).join(", ")}`
                  : ""}
              </dd>
            </dl>
            {team && teamStatus && (
              <TeamPanel
                team={team}
                status={teamStatus}
                events={live.status.events}
                selected={member?.vehicle ?? null}
                onSelect={(vehicle) => setMemberIndex(Math.max(0, team.findIndex((m) => m.vehicle === vehicle)))}
              />
            )}
            {faultNotice && (
              <p className="notice" role="status" data-testid="fault-notice">
                {faultNotice}
              </p>
            )}
            {live.source === "manual" && waiting && question && (
              <p className="question" data-testid="rehearsal-question">
                {question}
                {suggested?.outcome && (
                  <>
                    {" "}
                    <span className="hint">
                      The simulation saw: {OUTCOME_LABEL[suggested.outcome as Outcome] ?? suggested.outcome}
                      {suggested.because ? ` (${suggested.because})` : ""}.
                    </span>
                  </>
                )}
              </p>
            )}
            {live.source === "manual" && (
              <div className="button-row" role="group" aria-label="Outcome of the current goal">
                {OUTCOMES.map((o) => (
                  <button
                    key={o}
                    type="button"
                    disabled={busy || !waiting}
                    data-testid={`outcome-${o}`}
                    aria-keyshortcuts={KEY_OF[o]}
                    onClick={() => choose(o)}
                  >
                    {OUTCOME_LABEL[o]} <kbd>{KEY_OF[o]}</kbd>
                  </button>
                ))}
              </div>
            )}
            <button
              type="button"
              className="secondary"
              disabled={busy || state !== "running"}
              data-testid="skip-rehearsal"
              onClick={() =>
                void act(async () => setLive(await send({ rehearsal: live.id, skip: true })))
              }
            >
              Skip to the next decision
            </button>
            <div
              className="button-row"
              role="group"
              aria-label={member ? `Inject a fault into ${member.vehicle}` : "Inject a fault"}
            >
              {FAULTS.map((f) => (
                <button
                  key={f.value}
                  type="button"
                  className="secondary"
                  disabled={busy || finished}
                  data-testid={`fault-${f.value}`}
                  onClick={() =>
                    void act(async () => {
                      setFaultNotice(null);
                      const answer = await send({ rehearsal: live.id, fault: member ? `${member.vehicle}:${f.value}` : f.value });
                      setLive(answer);
                      setFaultNotice(answer.status.fault_notice?.text ?? `${f.label}: sent.`);
                    })
                  }
                >
                  {f.label}
                </button>
              ))}
            </div>
            <button
              type="button"
              disabled={busy}
              data-testid="stop-rehearsal"
              onClick={() =>
                void act(async () => {
                  // Listed at once from the stop's answer (the record is stored by then).
                  await stop.mutateAsync(live.id);
                  setLive(null);
                  setFaultNotice(null);
                })
              }
            >
              Stop and record
            </button>
          </div>
          <iframe
            title="3D rehearsal (viser)"
            src={live.viewer}
            className="viser-frame"
            data-testid="viser-frame"
            allow="fullscreen"
            // An opaque origin: the viewer cannot reach this app's storage, keys or API.
            sandbox="allow-scripts"
          />
          <MissionGraph
            orders={member ? member.orders : mission.orders}
            current={currentGoal}
            visited={memberStatus ? new Set(memberStatus.outcomes.map((o) => o.goal)) : outcomeGoals(live.status)}
            label={member ? `Mission graph of ${member.vehicle}` : "Mission graph"}
          />
        </div>
      )}
      <h3>Records</h3>
      {records.isPending ? (
        <Loading what="the rehearsal records" />
      ) : records.data && records.data.length > 0 ? (
        <ul className="records" data-testid="rehearsal-records">
          {records.data.map((r) => (
            <li key={r.digest}>
              <code title={r.digest}>{shortDigest(r.digest)}</code> · {r.source}
              {r.version ? ` · version ${r.version}` : " · draft"} · {r.owner ?? "—"} ·{" "}
              <time dateTime={String(r.created_at)}>{formatDateTime(String(r.created_at))}</time> ·{" "}
              <a href={r.replay} target="_blank" rel="noopener">
                Replay
              </a>{" "}
              · <a href={`/api/rehearsal-records/${encodeURIComponent(r.digest)}`}>Record (JSON)</a>
            </li>
          ))}
        </ul>
      ) : (
        <p className="empty">No rehearsal has been recorded for this mission yet.</p>
      )}
      {records.error instanceof ApiError && <ErrorMessage error={records.error} />}
    </>
  );
}

function outcomeGoals(status: Status): Set<string> {
  return new Set(status.outcomes.map((o) => o.goal));
}

type StartBody = {
  source: Source;
  seed: number;
  speed: number | null;
  path_index?: number | null;
  faults: string[];
  version?: number | null;
  member_paths?: MemberPaths;
};

function StartForm({
  mission,
  team,
  vehicles,
  busy,
  onStart,
}: {
  mission: MissionDetail;
  team: boolean;
  vehicles: string[];
  busy: boolean;
  onStart: (body: StartBody) => void;
}) {
  // A team's vehicles take their outcomes from their simulations; meetings are joint.
  const [source, setSource] = useState<Source>(team ? "simulate" : "manual");
  const [seed, setSeed] = useState(0);
  // Empty: the auto pace (each goal's plan in about three seconds).
  const [speed, setSpeed] = useState("");
  const [pathIndex, setPathIndex] = useState(1);
  const [version, setVersion] = useState<string>("");
  const [faults, setFaults] = useState<string[]>([]);
  const [memberPaths, setMemberPaths] = useState<MemberPaths>({});
  return (
    <form
      className="rehearsal-start"
      onSubmit={(event) => {
        event.preventDefault();
        onStart({
          source,
          seed,
          speed: speed.trim() === "" ? null : Number(speed),
          path_index: source === "replay" ? pathIndex : null,
          faults,
          version: version ? Number(version) : null,
          ...(team ? { member_paths: memberPaths } : {}),
        });
      }}
    >
      <label>
        Orders
        <select value={version} onChange={(e) => setVersion(e.target.value)} data-testid="rehearsal-version">
          <option value="">Current draft</option>
          {mission.versions.map((v) => (
            <option key={v.number} value={String(v.number)}>
              Version {v.number}
            </option>
          ))}
        </select>
      </label>
      {team && (
        <p className="hint" data-testid="team-rehearsal-note">
          A team rehearses every vehicle in one scene and one clock: each vehicle&apos;s outcomes come from its
          simulation or a replayed path of its own orders, and a vehicle at a meeting holds there until its partners
          come; the meeting then ends for all with one shared outcome.
        </p>
      )}
      {team && <TeamMemberSources vehicles={vehicles} value={memberPaths} onChange={setMemberPaths} />}
      <label>
        Outcomes
        <select value={source} onChange={(e) => setSource(e.target.value as Source)} data-testid="rehearsal-source">
          {SOURCES.filter((s) => !team || s.value === "simulate").map((s) => (
            <option key={s.value} value={s.value}>
              {s.label}
            </option>
          ))}
        </select>
      </label>
      {source === "replay" && (
        <label>
          Path number
          <input type="number" min={1} value={pathIndex} onChange={(e) => setPathIndex(Number(e.target.value) || 1)} />
        </label>
      )}
      <label>
        Seed
        <input type="number" min={0} value={seed} onChange={(e) => setSeed(Number(e.target.value) || 0)} />
      </label>
      <label>
        Speed (× real time; empty: auto, each goal in about 3 s)
        <input
          type="number"
          min={0.1}
          max={100000}
          step="any"
          placeholder="auto"
          value={speed}
          onChange={(e) => setSpeed(e.target.value)}
          data-testid="rehearsal-speed"
        />
      </label>
      {source === "simulate" && (
        <fieldset>
          <legend>{team ? "Faults from the start (every vehicle)" : "Faults from the start"}</legend>
          {FAULTS.map((f) => (
            <label key={f.value} className="inline">
              <input
                type="checkbox"
                checked={faults.includes(f.value)}
                onChange={(e) =>
                  setFaults(e.target.checked ? [...faults, f.value] : faults.filter((x) => x !== f.value))
                }
              />{" "}
              {f.label}
            </label>
          ))}
        </fieldset>
      )}
      <button type="submit" disabled={busy} data-testid="start-rehearsal">
        Start rehearsal
      </button>
    </form>
  );
}

/** A team's rehearsal: the vehicle switcher, each vehicle (its scene colour, state, goal and
 * energy), the meetings that happened, the joint end, and the latest events naming their
 * vehicle. Every name is the orders' text, shown as text. */
function TeamPanel({
  team,
  status,
  events,
  selected,
  onSelect,
}: {
  team: MemberSpec[];
  status: TeamStatus;
  events: Status["events"];
  selected: string | null;
  onSelect: (vehicle: string) => void;
}) {
  const latest = events.slice(-6);
  return (
    <section className="team-rehearsal" aria-label="Team" data-testid="team-rehearsal">
      <label className="team-switcher">
        Vehicle:{" "}
        <select value={selected ?? ""} onChange={(e) => onSelect(e.target.value)} data-testid="team-member">
          {team.map((m) => (
            <option key={m.vehicle} value={m.vehicle}>
              {m.vehicle}
            </option>
          ))}
        </select>
      </label>
      <ul className="team-members" data-testid="team-members">
        {status.members.map((m, i) => (
          <li key={m.vehicle} className={m.vehicle === selected ? "selected" : undefined} data-testid="team-member-row">
            <span className="swatch" style={{ background: VEHICLE_COLOURS[i % VEHICLE_COLOURS.length] }} aria-hidden="true" />
            <strong>{m.vehicle}</strong> {MEMBER_STATE[m.state]}
            {m.current_goal ? ` · ${m.current_goal.id}` : m.terminal ? ` · ${m.terminal}` : ""} ·{" "}
            {`${m.energy_wh.toFixed(0)} Wh left`}
          </li>
        ))}
      </ul>
      <p data-testid="team-meetings">
        {status.meetings.length
          ? status.meetings
              .map(
                (m) =>
                  `Meeting ${m.meet}: ${OUTCOME_LABEL[m.outcome as Outcome] ?? m.outcome} at ${simulatedTime(m.t)} (${Object.entries(m.goals)
                    .map(([v, g]) => `${v} ${g}`)
                    .join(", ")})`,
              )
              .join("; ")
          : "No meeting yet."}
      </p>
      {status.joint_end && <p data-testid="team-joint-end">Joint end: {status.joint_end}</p>}
      <ol className="team-events" aria-label="Latest events" data-testid="team-events">
        {latest.map((e, i) => (
          <li key={`${e.t}-${i}`} className={e.kind === "deadlock" ? "deadlock" : undefined}>
            <strong>{e.vehicle ?? ""}</strong>
            {e.goal ? ` ${e.goal}` : ""}: {e.text}
          </li>
        ))}
      </ol>
    </section>
  );
}

/** The mission graph as goal cards in the order it is flown (rehearsalOrder.ts), the current
 * goal highlighted. */
function MissionGraph({
  orders,
  current,
  visited,
  label = "Mission graph",
}: {
  orders: Orders;
  current: string | null;
  visited: Set<string>;
  label?: string;
}) {
  const all = goals(orders);
  const order = pathOrder(orders);
  const ends = new Map(terminals(orders).map((t) => [t.id, t]));
  // A refined mission runs as its flat form: the current goal may be a step inside a
  // refinement (`G1/G1.2#3`); its refined goal is current on the mission's level.
  const place = current ? stepPlace(current) : null;
  const visitedTop = new Set([...visited].map((v) => stepPlace(v).top));
  const visitedInner = new Set([...visited].map((v) => stepPlace(v).full));
  return (
    <ol className="rehearsal-graph" aria-label={label} data-testid="rehearsal-graph">
      {order.map((id) => {
        const goal = all.find((g) => g.id === id)!;
        const isCurrent = id === place?.top;
        const inner = goal.refines?.goals ?? [];
        return (
          <li
            key={id}
            className={isCurrent ? "goal current" : visitedTop.has(id) ? "goal visited" : "goal"}
            aria-current={isCurrent && inner.length === 0 ? "step" : undefined}
            data-testid={isCurrent ? "graph-current" : undefined}
          >
            <strong>{goal.title || id}</strong> <code>{id}</code>
            {inner.length > 0 && (
              <ol className="rehearsal-refinement" aria-label={`Refinement of ${id}`} data-testid={`rehearsal-refinement-${id}`}>
                {inner.map((g) => {
                  const full = `${id}/${g.id}`;
                  const here = place !== null && (place.full === full || place.full.startsWith(`${full}/`));
                  return (
                    <li
                      key={g.id}
                      className={here ? "step current" : visitedInner.has(full) ? "step visited" : "step"}
                      aria-current={here ? "step" : undefined}
                      data-testid={here ? "graph-current-step" : undefined}
                    >
                      <code>{full}</code> {g.title || ""}
                    </li>
                  );
                })}
              </ol>
            )}
            <ul>
              {OUTCOMES.map((o: Outcome) => {
                const targets = successors(goal, o);
                return (
                  <li key={o} className={`edge edge-${o}`}>
                    {OUTCOME_LABEL[o].split(" ")[0]} →{" "}
                    {targets.length
                      ? targets.map((t) => (ends.has(t) ? `${t} (${ends.get(t)!.kind})` : t)).join(", ")
                      : "—"}
                  </li>
                );
              })}
            </ul>
          </li>
        );
      })}
    </ol>
  );
}

export default RehearsalPanel;
