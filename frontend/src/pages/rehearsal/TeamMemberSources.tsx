/**
 * Where each vehicle of a team rehearsal takes its outcomes: its simulation, or one traversal
 * path of its own orders replayed (the API's `member_paths`, as the CLI's
 * `--member-path vehicle-2=19`). Meetings stay joint either way: a replayed member's path
 * decides the shared outcome of the meetings it reaches first (README "Teams").
 */
import "./teamSources.css";

/** The member paths the API takes: only replayed vehicles, each with its path number. */
export type MemberPaths = Record<string, number>;

export function TeamMemberSources({
  vehicles,
  value,
  onChange,
}: {
  vehicles: string[];
  value: MemberPaths;
  onChange: (next: MemberPaths) => void;
}) {
  const set = (vehicle: string, path: number | null) => {
    const next = { ...value };
    if (path === null) delete next[vehicle];
    else next[vehicle] = path;
    onChange(next);
  };
  return (
    <fieldset className="team-sources" data-testid="team-sources">
      <legend>Each vehicle&apos;s outcomes</legend>
      {vehicles.map((vehicle, index) => {
        const path = value[vehicle];
        const id = `team-source-${index}`;
        return (
          <div className="team-source" key={vehicle} data-testid="team-source">
            <label htmlFor={id} className="team-source-vehicle">
              {vehicle}
            </label>
            <select
              id={id}
              value={path === undefined ? "simulate" : "replay"}
              onChange={(e) => set(vehicle, e.target.value === "replay" ? (path ?? 1) : null)}
              data-testid="team-source-kind"
            >
              <option value="simulate">Simulate</option>
              <option value="replay">Replay path</option>
            </select>
            {path !== undefined && (
              <label className="team-source-path">
                Path number
                <input
                  type="number"
                  min={1}
                  step={1}
                  value={path}
                  onChange={(e) => set(vehicle, Math.max(1, Math.floor(Number(e.target.value)) || 1))}
                  data-testid="team-source-path"
                />
              </label>
            )}
          </div>
        );
      })}
      <p className="hint">A replayed path is numbered as the vehicle&apos;s own orders number their paths (Paths tab).</p>
    </fieldset>
  );
}
