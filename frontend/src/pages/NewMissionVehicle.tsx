/**
 * The create form's vehicle: picked from the server's vehicle registry, so a
 * new mission is checked against a registered profile from its first save, instead of a
 * free-text default that opened every new mission with a VEHICLE error. "Other id" keeps a
 * vehicle the registry does not know yet (VEHICLE says so until an admin adds its profile).
 */
import { useEffect, useState } from "react";

import { idAndTitle } from "../editor/pickers";
import { useVehicles } from "../api/vehicles";

const OTHER = " other"; // not a valid id, so no vehicle can be confused with it

export function NewMissionVehicle({ value, onChange }: { value: string; onChange: (id: string) => void }) {
  const { data: known, isPending: loading } = useVehicles();
  const [other, setOther] = useState(false);
  const registered = known ?? [];
  // The first registered vehicle until the user chooses (an empty registry: none).
  useEffect(() => {
    if (!loading && value === "" && !other && registered[0]) onChange(registered[0].id);
  }, [loading, registered, value, other, onChange]);
  const listed = registered.some((v) => v.id === value);
  const selected = other || (value !== "" && !listed) ? OTHER : value;
  return (
    <>
      <label htmlFor="new-vehicle">Vehicle</label>
      <select
        id="new-vehicle"
        value={selected}
        disabled={loading && !known}
        onChange={(e) => {
          const chosen = e.target.value;
          setOther(chosen === OTHER);
          onChange(chosen === OTHER ? "" : chosen);
        }}
      >
        <option value="">none yet (choose in the editor)</option>
        {registered.map((v) => (
          <option key={v.id} value={v.id}>
            {idAndTitle(v.id, v.title)}
          </option>
        ))}
        <option value={OTHER}>Other id…</option>
      </select>
      {selected === OTHER && (
        <>
          <label htmlFor="new-vehicle-other">Vehicle id (not in the registry)</label>
          <input id="new-vehicle-other" value={value} maxLength={100} onChange={(e) => onChange(e.target.value)} />
          <p className="hint">VEHICLE reports this mission until an admin adds the profile on the Vehicles page.</p>
        </>
      )}
      {!loading && registered.length === 0 && (
        <p className="hint" data-testid="empty-registry">
          The vehicle registry is empty: an admin adds profiles on the Vehicles page.
        </p>
      )}
    </>
  );
}
