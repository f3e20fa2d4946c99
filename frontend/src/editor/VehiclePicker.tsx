/**
 * The mission's target vehicle, picked from the server's vehicle registry (and the profiles the
 * orders carry); "Other id" keeps a vehicle the registry does not know yet, which VEHICLE then
 * reports until a profile is added. The goal inspector's behaviour suggestions come from the
 * target vehicle's trusted behaviours, in the orders or else in the registry.
 */
import { useEffect, useState } from "react";

import { loadVehicles, type RegistryProfile } from "../pages/vehicles/api";
import { CommitField } from "./fields";

// Not a valid id (ids have no spaces), so no vehicle can be confused with it.
const OTHER = " other";
const FALLBACK_BEHAVIOURS = ["area_search", "sample", "rendezvous", "transit", "recover"];

type Carried = { id: string; title?: string; behaviors?: string[] };

// One registry read per page, shared by the picker and the behaviour suggestions.
let registry: Promise<RegistryProfile[]> | null = null;
function useRegistry(): RegistryProfile[] {
  const [list, setList] = useState<RegistryProfile[]>([]);
  useEffect(() => {
    let live = true;
    registry ??= loadVehicles().catch(() => {
      registry = null;
      return [];
    });
    void registry.then((found) => live && setList(found));
    return () => {
      live = false;
    };
  }, []);
  return list;
}

export function VehiclePicker({
  value,
  carried,
  onChange,
}: {
  value: string;
  carried: Carried[];
  onChange: (id: string | undefined) => void;
}) {
  const known = useRegistry();
  const options = new Map<string, string>();
  for (const v of known) options.set(v.id, v.title ? `${v.id}: ${v.title} (registry)` : `${v.id} (registry)`);
  for (const v of carried) if (!options.has(v.id)) options.set(v.id, v.title ? `${v.id}: ${v.title} (in these orders)` : `${v.id} (in these orders)`);
  const [other, setOther] = useState(false);
  const listed = value !== "" && options.has(value);
  const selected = other || (value !== "" && !listed) ? OTHER : value;
  return (
    <>
      <label htmlFor="mission-vehicle-pick">Target vehicle</label>
      <select
        id="mission-vehicle-pick"
        value={selected}
        onChange={(e) => {
          const next = e.target.value;
          setOther(next === OTHER);
          if (next !== OTHER) onChange(next || undefined);
        }}
      >
        <option value="">— none —</option>
        {[...options].map(([id, label]) => (
          <option key={id} value={id}>
            {label}
          </option>
        ))}
        <option value={OTHER}>Other id (not in the registry)…</option>
      </select>
      {selected === OTHER && (
        <CommitField
          id="mission-vehicle"
          label="Target vehicle (id)"
          value={value}
          onCommit={(text) => {
            onChange(text.trim() || undefined);
          }}
        />
      )}
    </>
  );
}

/** The datalist of behaviours the goal inspector suggests (id "behaviour-options"). */
export function BehaviourOptions({ vehicle, carried }: { vehicle: string | undefined; carried: Carried[] }) {
  const known = useRegistry();
  const profile = carried.find((v) => v.id === vehicle) ?? known.find((v) => v.id === vehicle);
  return (
    <datalist id="behaviour-options">
      {(profile?.behaviors ?? FALLBACK_BEHAVIOURS).map((b) => (
        <option key={b} value={b} />
      ))}
    </datalist>
  );
}
