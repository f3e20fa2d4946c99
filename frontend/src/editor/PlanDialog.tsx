/**
 * "Plan survey": builds a countersign.plan/1 problem from the saved draft's areas and
 * vehicle (the server lays lawn-mower passes over each polygon), lets the operator set level,
 * battery, reserve, rewards and mandatory areas, solves it exactly on the server, shows the
 * chosen order and passes on the plan view, and creates a new draft from the plan's orders.
 */
import { useEffect, useMemo, useRef, useState } from "react";

import { ApiError, type MissionDetail, type Schema } from "../api/client";
import { useCreateMission } from "../api/missions";
import { buildPlanProblem, solvePlan } from "../api/plans";
import { type Column, DataTable } from "../components/DataTable";
import { ErrorMessage } from "../components/Status";
import { formatNumber } from "../format";
import { navigate } from "../navigation";
import { missionHref } from "../router";
import type { Orders } from "./graph";
import { areas, type LatLon, targetVehicle } from "./model";
import type { PlanOverlay } from "./panels";
import { SurveyMap } from "../map/SurveyMap";
import { centroid, fromMetres, round6 } from "./planview";

/** The countersign.plan/1 problem the server built from the draft (lawn-mower passes). */
type Problem = Schema<"PlanProblem">;
/** POST /api/plan: the best plan, or why there is none. */
type Solution = Schema<"PlanOut">;

type Area = ReturnType<typeof areas>[number];

/** What the operator chose for each area: included, its reward, mandatory. */
interface AreaChoices {
  included: Record<string, boolean>;
  setIncluded: (next: Record<string, boolean>) => void;
  rewards: Record<string, string>;
  setRewards: (next: Record<string, string>) => void;
  mandatory: Record<string, boolean>;
  setMandatory: (next: Record<string, boolean>) => void;
}

/** An area a row: its id and title, then the operator's choices for it. */
function areaColumns({ included, setIncluded, rewards, setRewards, mandatory, setMandatory }: AreaChoices): Column<Area>[] {
  return [
    { header: "Area", rowHeader: true, cell: (a) => `${a.id}${a.title ? `: ${a.title}` : ""}` },
    {
      header: "Include",
      cell: (a) => (
        <input
          type="checkbox"
          aria-label={`Include ${a.id}`}
          checked={!!included[a.id]}
          onChange={(e) => setIncluded({ ...included, [a.id]: e.target.checked })}
        />
      ),
    },
    {
      header: "Reward",
      cell: (a) => (
        <input
          type="number"
          step="any"
          min={0}
          aria-label={`Reward of ${a.id}`}
          value={rewards[a.id] ?? ""}
          onChange={(e) => setRewards({ ...rewards, [a.id]: e.target.value })}
        />
      ),
    },
    {
      header: "Mandatory",
      cell: (a) => (
        <input
          type="checkbox"
          aria-label={`${a.id} is mandatory`}
          checked={!!mandatory[a.id]}
          onChange={(e) => setMandatory({ ...mandatory, [a.id]: e.target.checked })}
        />
      ),
    },
  ];
}

// Length: one modal dialog: the survey plan's inputs, its map and the plan it answers.
export function PlanDialog({ mission, orders, onClose }: { mission: MissionDetail; orders: Orders; onClose: () => void }) {
  const withPolygons = areas(orders).filter((a) => (a.polygon ?? []).length >= 3);
  const vehicle = targetVehicle(orders);
  const base = withPolygons.find((a) => a.contexts?.includes("harbor_approach")) ?? withPolygons[withPolygons.length - 1];
  const home: LatLon = base ? centroid(base.polygon ?? []) : [0, 0];
  const [level, setLevel] = useState(2);
  const [start, setStart] = useState<[string, string]>([String(round6(home[0])), String(round6(home[1]))]);
  const [recovery, setRecovery] = useState<[string, string]>([String(round6(home[0])), String(round6(home[1]))]);
  const [battery, setBattery] = useState(String(vehicle?.budget?.energy_wh ?? ""));
  const [reserve, setReserve] = useState("0");
  const [swath, setSwath] = useState("");
  const [included, setIncluded] = useState<Record<string, boolean>>(() =>
    Object.fromEntries(withPolygons.map((a) => [a.id, a.id !== base?.id])),
  );
  const [rewards, setRewards] = useState<Record<string, string>>(() => Object.fromEntries(withPolygons.map((a) => [a.id, "1"])));
  const [mandatory, setMandatory] = useState<Record<string, boolean>>({});
  const [solving, setBusy] = useState(false);
  const createMission = useCreateMission();
  const busy = solving || createMission.isPending;
  const [error, setError] = useState<unknown>(null);
  const [problem, setProblem] = useState<Problem | null>(null);
  const [solution, setSolution] = useState<Solution | null>(null);
  const [newId, setNewId] = useState(`${mission.id}-plan`);
  const heading = useRef<HTMLHeadingElement>(null);
  useEffect(() => heading.current?.focus(), []);

  const num = (t: string) => (t.trim() === "" ? undefined : Number(t));
  const solve = async () => {
    setBusy(true);
    setError(null);
    setSolution(null);
    try {
      const chosen = withPolygons.filter((a) => included[a.id]).map((a) => a.id);
      const body = {
        start: [Number(start[0]), Number(start[1])] as [number, number],
        recovery: [Number(recovery[0]), Number(recovery[1])] as [number, number],
        battery_wh: num(battery) ?? null,
        reserve_wh: num(reserve) ?? 0,
        swath_m: num(swath) ?? null,
        level,
        areas: chosen,
        rewards: Object.fromEntries(chosen.map((id) => [id, Number(rewards[id] ?? 1)])),
        mandatory: chosen.filter((id) => mandatory[id]),
      };
      const built = await buildPlanProblem(mission.id, body);
      setProblem(built);
      const solved = await solvePlan(built);
      setSolution(solved);
    } catch (e) {
      setError(e);
    } finally {
      setBusy(false);
    }
  };

  const overlay: PlanOverlay | null = useMemo(() => {
    if (!problem || !solution?.feasible || !solution.order) return null;
    const origin: LatLon = [Number(start[0]), Number(start[1])];
    const route: PlanOverlay["route"] = [{ at: fromMetres(origin, problem.start), label: "start" }];
    solution.order.forEach((id, i) => {
      const area = problem.areas?.find((a) => a.id === id);
      const pass = area?.passes[solution.passes?.[id] ?? 0];
      if (!pass) return;
      route.push({ at: fromMetres(origin, pass.entry), label: `${i + 1}. ${id} in` });
      route.push({ at: fromMetres(origin, pass.exit), label: `${id} out` });
    });
    route.push({ at: fromMetres(origin, problem.recovery), label: "recovery" });
    return { route, chosen: solution.order };
  }, [problem, solution, start]);

  const createDraft = async () => {
    if (!solution?.orders) return;
    setError(null);
    try {
      const body = { ...solution.orders, id: newId.trim(), title: `Survey plan from ${orders.title || mission.id}` };
      const created = await createMission.mutateAsync(body);
      navigate(missionHref(created.id, "editor"));
      onClose();
    } catch (e) {
      setError(e instanceof ApiError ? e : String(e));
    }
  };

  const pair = (label: string, value: [string, string], set: (v: [string, string]) => void, id: string) => (
    <div className="pair">
      <span>
        <label htmlFor={`${id}-lat`}>{label} latitude</label>
        <input id={`${id}-lat`} type="number" step="any" value={value[0]} onChange={(e) => set([e.target.value, value[1]])} />
      </span>
      <span>
        <label htmlFor={`${id}-lon`}>{label} longitude</label>
        <input id={`${id}-lon`} type="number" step="any" value={value[1]} onChange={(e) => set([value[0], e.target.value])} />
      </span>
    </div>
  );

  return (
    <div className="dialog-backdrop">
      <div
        role="dialog"
        aria-modal="true"
        aria-labelledby="plan-title"
        className="dialog plan-dialog"
        onKeyDown={(e) => {
          if (e.key === "Escape") onClose();
        }}
      >
        <h3 id="plan-title" tabIndex={-1} ref={heading}>
          Plan survey
        </h3>
        {withPolygons.length === 0 || !vehicle ? (
          <p className="message">The plan needs areas with polygons and a vehicle profile with speed and power.</p>
        ) : (
          <form
            onSubmit={(e) => {
              e.preventDefault();
              void solve();
            }}
          >
            <p className="hint">Built from the saved draft: lawn-mower passes over each area, energy from the vehicle's speed and power.</p>
            <label htmlFor="plan-level">Level</label>
            <select id="plan-level" value={level} onChange={(e) => setLevel(Number(e.target.value))}>
              <option value={1}>1: order only</option>
              <option value={2}>2: order and entry/exit</option>
            </select>
            {pair("Start", start, setStart, "plan-start")}
            {pair("Recovery", recovery, setRecovery, "plan-recovery")}
            <div className="pair">
              <span>
                <label htmlFor="plan-battery">Battery (Wh)</label>
                <input id="plan-battery" type="number" step="any" min={0} value={battery} onChange={(e) => setBattery(e.target.value)} />
              </span>
              <span>
                <label htmlFor="plan-reserve">Reserve (Wh)</label>
                <input id="plan-reserve" type="number" step="any" min={0} value={reserve} onChange={(e) => setReserve(e.target.value)} />
              </span>
              <span>
                <label htmlFor="plan-swath">Swath (m, optional)</label>
                <input id="plan-swath" type="number" step="any" min={0} value={swath} onChange={(e) => setSwath(e.target.value)} />
              </span>
            </div>
            <DataTable
              caption="Areas to consider"
              showCaption
              className="plan-areas"
              rows={withPolygons}
              rowKey={(a) => a.id}
              columns={areaColumns({ included, setIncluded, rewards, setRewards, mandatory, setMandatory })}
            />
            <button type="submit" disabled={busy}>
              {busy ? "Solving…" : "Solve"}
            </button>
          </form>
        )}
        <ErrorMessage error={error} />
        {solution && (
          <div data-testid="plan-result" role="status">
            {solution.feasible ? (
              <p>
                Best plan: {solution.order?.join(" → ") || "no area"} — reward {formatNumber(solution.reward ?? 0)}, energy{" "}
                {formatNumber(Math.round(solution.energy_wh ?? 0))} Wh of {formatNumber(Math.round(solution.limit_wh ?? 0))} Wh.
                {solution.order && solution.order.length > 0 && (
                  <> Passes: {solution.order.map((id) => `${id} #${(solution.passes?.[id] ?? 0) + 1}`).join(", ")}.</>
                )}
              </p>
            ) : (
              <p className="message error">
                No feasible plan: {solution.message} {solution.conflict?.length ? `(mandatory areas that cannot be served together: ${solution.conflict.join(", ")})` : ""}
              </p>
            )}
          </div>
        )}
        <SurveyMap orders={orders} overlay={overlay} title="Plan view with the chosen survey order" />
        {solution?.feasible && solution.orders && (
          <form
            className="inline"
            onSubmit={(e) => {
              e.preventDefault();
              void createDraft();
            }}
          >
            <label htmlFor="plan-new-id">New mission id</label>
            <input id="plan-new-id" value={newId} onChange={(e) => setNewId(e.target.value)} />
            <button type="submit" disabled={busy || !newId.trim()}>
              Create draft from plan
            </button>
          </form>
        )}
        <div className="actions">
          <button type="button" onClick={onClose}>
            Close
          </button>
        </div>
      </div>
    </div>
  );
}
