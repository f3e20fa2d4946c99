/**
 * The mission's target vehicle, picked from the server's vehicle registry (and the profiles the
 * orders carry), searchable by id and title; "Other id" keeps a vehicle the registry does not
 * know yet, which VEHICLE then reports until a profile is added. The goal inspector's behaviour
 * picker offers the target vehicle's trusted behaviours, in the orders or else in the registry.
 */
import { useEffect, useState } from "react";

import { loadVehicles, type RegistryProfile } from "../api/vehicles";
import { CommitField, Picker } from "./fields";
import { type BehaviourProfile, behaviourChoices, type Choice, idAndTitle, trustedBehaviours } from "./pickers";

// Not a valid id (ids have no spaces), so no vehicle can be confused with it.
const OTHER = " other";
const FALLBACK_BEHAVIOURS = ["area_search", "sample", "rendezvous", "transit", "recover"];

type Carried = BehaviourProfile & { id: string; title?: string };

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
  const choices: Choice[] = [{ value: "", label: "— none —" }];
  const listed = new Set<string>();
  for (const v of known) {
    listed.add(v.id);
    choices.push({ value: v.id, label: idAndTitle(v.id, v.title), detail: "registry" });
  }
  for (const v of carried) {
    if (listed.has(v.id)) continue;
    listed.add(v.id);
    choices.push({ value: v.id, label: idAndTitle(v.id, v.title), detail: "in these orders" });
  }
  const [other, setOther] = useState(false);
  const unlisted = value !== "" && !listed.has(value);
  if (unlisted) choices.push({ value, label: value, detail: "not in the registry: VEHICLE until a profile is added" });
  choices.push({ value: OTHER, label: "Other id (not in the registry)…" });
  return (
    <>
      <Picker
        id="mission-vehicle-pick"
        label="Target vehicle"
        value={other ? OTHER : value}
        choices={choices}
        onCommit={(next) => {
          setOther(next === OTHER);
          if (next !== OTHER) onChange(next || undefined);
        }}
      />
      {(other || unlisted) && (
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

/** The trusted behaviours of the target vehicle: its profile in the orders, else the registry's;
 * null when neither has one. */
function useTrustedBehaviours(vehicle: string | undefined, carried: Carried[]): string[] | null {
  const known = useRegistry();
  const profile = carried.find((v) => v.id === vehicle) ?? known.find((v) => v.id === vehicle);
  return profile ? trustedBehaviours(profile) : null;
}

/**
 * A goal's behaviour, picked from the target vehicle's trusted behaviours (seed 000 III.D: every
 * phase is an available trusted behaviour). "Other behaviour…" types one the vehicle does not
 * list (imported orders may need it); M7 then reports it.
 */
export function BehaviourPicker({
  value,
  vehicle,
  carried,
  onChange,
}: {
  value: string;
  vehicle: string | undefined;
  carried: Carried[];
  onChange: (behaviour: string | undefined) => void;
}) {
  const trusted = useTrustedBehaviours(vehicle, carried);
  const [other, setOther] = useState(false);
  const choices = [...behaviourChoices(trusted ?? FALLBACK_BEHAVIOURS, value || undefined, trusted ? vehicle : undefined)];
  if (!trusted) for (const c of choices) if (c.value && !c.detail) c.detail = "common; the vehicle has no profile";
  choices.push({ value: OTHER, label: "Other behaviour…" });
  const untrusted = value !== "" && trusted !== null && !trusted.includes(value);
  return (
    <>
      <Picker
        id="goal-behavior"
        label="Behaviour"
        value={other ? OTHER : value}
        choices={choices}
        describedBy="goal-behavior-hint"
        onCommit={(next) => {
          setOther(next === OTHER);
          if (next !== OTHER) onChange(next || undefined);
        }}
      />
      <span id="goal-behavior-hint" className="hint">
        {trusted === null
          ? vehicle
            ? `No profile for ${vehicle} yet: common behaviours are offered.`
            : "No target vehicle: common behaviours are offered."
          : untrusted
            ? `${value} is not a trusted behaviour of ${vehicle}.`
            : `The trusted behaviours of ${vehicle}.`}
      </span>
      {other && (
        <CommitField
          id="goal-behavior-other"
          label="Other behaviour (name)"
          value={value}
          onCommit={(text) => {
            onChange(text.trim() || undefined);
            setOther(false);
          }}
        />
      )}
    </>
  );
}
