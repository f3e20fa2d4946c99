/**
 * A vehicle profile edited as a form: trusted behaviours, speed, budget, the
 * envelope (one row per quantity: min and max) and the features (id, what each fulfils and
 * measures). The form edits the same profile the JSON box below it shows, so fields it has no
 * input for (contingency rules, consumption) are kept as they are. The server checks the saved
 * profile and names a refused field (the inputs carry no min/max of their own, so the browser
 * never blocks a save the server would explain).
 */
import type { ReactNode } from "react";

import type { RegistryProfile } from "../../api/vehicles";
import type { Column } from "../../components/DataTable";
import { EditableTable } from "../../components/EditableTable";
import "./vehicles.css";

type Profile = RegistryProfile & Record<string, unknown>;
type Feature = { id: string; fulfills?: string[]; measures?: string[] } & Record<string, unknown>;

const words = (text: string) => text.split(",").map((w) => w.trim()).filter(Boolean);
const number = (text: string): number | undefined => (text.trim() === "" || !Number.isFinite(Number(text)) ? undefined : Number(text));

/** The profile with `key` set, or removed when the value is empty (the server stores no defaults). */
function withField(profile: Profile, key: string, value: unknown): Profile {
  const next: Profile = { ...profile };
  const empty = value === undefined || (Array.isArray(value) && value.length === 0) || (typeof value === "object" && value !== null && !Array.isArray(value) && Object.keys(value).length === 0);
  if (empty) delete next[key];
  else next[key] = value;
  return next;
}

function Row({ children }: { children: ReactNode }) {
  return <div className="profile-row">{children}</div>;
}

/** A label and its input, kept together: when a row wraps, the pair moves to the next line as
 * one (never a label ending a line with its input on the next), and a pair too narrow for both
 * puts the input directly under its label. */
function Field({ children }: { children: ReactNode }) {
  return <span className="profile-field">{children}</span>;
}

/** One number of the profile (speed, a budget) in a Field; an empty input is undefined. */
function NumberField({ id, label, value, onChange }: { id: string; label: string; value: number | undefined; onChange: (value: number | undefined) => void }) {
  return (
    <Field>
      <label htmlFor={id}>{label}</label>
      <input id={id} type="number" step="any" value={value ?? ""} onChange={(e) => onChange(number(e.target.value))} />
    </Field>
  );
}

type Envelope = Record<string, [number, number]>;

/** A quantity a row, its min and max (an empty field is 0: the server names a refused range). */
function envelopeColumns(envelope: Envelope, setEnvelope: (next: Envelope) => void): Column<[string, [number, number]]>[] {
  const end = (at: 0 | 1): Column<[string, [number, number]]> => ({
    header: at === 0 ? "Min" : "Max",
    cell: ([quantity, range]) => (
      <input
        type="number"
        step="any"
        aria-label={`${quantity} ${at === 0 ? "min" : "max"}`}
        value={Array.isArray(range) ? (range[at] ?? "") : ""}
        onChange={(e) => {
          const next: [number, number] = [Array.isArray(range) ? range[0] : 0, Array.isArray(range) ? range[1] : 0];
          next[at] = number(e.target.value) ?? 0;
          setEnvelope({ ...envelope, [quantity]: next });
        }}
      />
    ),
  });
  return [{ header: "Quantity", rowHeader: true, cell: ([quantity]) => <code>{quantity}</code> }, end(0), end(1)];
}

/** A feature a row: its id, what it fulfils and what it measures. */
function featureColumns(setFeature: (i: number, changes: Partial<Feature>) => void): Column<Feature>[] {
  const name = (f: Feature, i: number) => f.id || `Feature ${i + 1}`;
  return [
    {
      header: "Feature",
      cell: (f, i) => <input aria-label={`Feature ${i + 1} id`} value={f.id ?? ""} maxLength={100} onChange={(e) => setFeature(i, { id: e.target.value })} />,
    },
    {
      header: "Fulfils (comma-separated)",
      cell: (f, i) => <input aria-label={`${name(f, i)} fulfils`} value={(f.fulfills ?? []).join(", ")} onChange={(e) => setFeature(i, { fulfills: words(e.target.value) })} />,
    },
    {
      header: "Measures (comma-separated)",
      cell: (f, i) => <input aria-label={`${name(f, i)} measures`} value={(f.measures ?? []).join(", ")} onChange={(e) => setFeature(i, { measures: words(e.target.value) })} />,
    },
  ];
}

export function ProfileForm({ profile, onChange, fixedId }: { profile: Profile; onChange: (p: Profile) => void; fixedId: boolean }) {
  const envelope = (profile.envelope ?? {}) as Envelope;
  const budget = (profile.budget ?? {}) as { energy_wh?: number; duration_s?: number };
  const setBudget = (changes: typeof budget) => onChange(withField(profile, "budget", { ...budget, ...changes }));
  const features = ((profile.features ?? []) as Feature[]).filter((f) => typeof f === "object" && f !== null);
  const setEnvelope = (next: Envelope) => onChange(withField(profile, "envelope", next));
  const setFeatures = (next: Feature[]) => onChange(withField(profile, "features", next));
  const setFeature = (i: number, changes: Partial<Feature>) => setFeatures(features.map((f, k) => (k === i ? { ...f, ...changes } : f)));
  return (
    <fieldset className="profile-form" data-testid="profile-form">
      <legend>Profile</legend>
      <Row>
        <Field>
          <label htmlFor="vehicle-id">Vehicle id</label>
          <input id="vehicle-id" value={profile.id ?? ""} readOnly={fixedId} maxLength={100} onChange={(e) => onChange({ ...profile, id: e.target.value })} />
        </Field>
        <Field>
          <label htmlFor="vehicle-title">Title</label>
          <input id="vehicle-title" value={(profile.title as string | undefined) ?? ""} maxLength={200} onChange={(e) => onChange(withField(profile, "title", e.target.value || undefined))} />
        </Field>
      </Row>
      <Row>
        <Field>
          <label htmlFor="vehicle-behaviors">Trusted behaviours (comma-separated)</label>
          <input
            id="vehicle-behaviors"
            value={((profile.behaviors as string[] | undefined) ?? []).join(", ")}
            onChange={(e) => onChange(withField(profile, "behaviors", words(e.target.value)))}
          />
        </Field>
      </Row>
      <Row>
        <NumberField
          id="vehicle-speed"
          label="Speed (m/s)"
          value={profile.speed_mps as number | undefined}
          onChange={(v) => onChange(withField(profile, "speed_mps", v))}
        />
        <NumberField id="vehicle-energy" label="Energy budget (Wh)" value={budget.energy_wh} onChange={(v) => setBudget({ energy_wh: v })} />
        <NumberField id="vehicle-duration" label="Time budget (s)" value={budget.duration_s} onChange={(v) => setBudget({ duration_s: v })} />
      </Row>
      <h3>Envelope</h3>
      <EditableTable
        caption="Envelope: limits per quantity"
        className="profile-table"
        columns={envelopeColumns(envelope, setEnvelope)}
        rows={Object.entries(envelope)}
        rowKey={([quantity]) => quantity}
        remove={{
          header: "Remove",
          text: ([quantity]) => `Remove ${quantity}`,
          onRemove: ([quantity]) => setEnvelope(Object.fromEntries(Object.entries(envelope).filter(([q]) => q !== quantity))),
        }}
      />
      <Row>
        <Field>
          <label htmlFor="vehicle-new-limit">New limit (quantity name)</label>
          <input
            id="vehicle-new-limit"
            placeholder="depth_m"
            maxLength={100}
            onKeyDown={(e) => {
              const name = e.currentTarget.value.trim();
              if (e.key !== "Enter" || !name) return;
              e.preventDefault();
              if (!(name in envelope)) setEnvelope({ ...envelope, [name]: [0, 0] });
              e.currentTarget.value = "";
            }}
          />
        </Field>
      </Row>
      <h3>Features</h3>
      <EditableTable
        caption="Features"
        className="profile-table"
        columns={featureColumns(setFeature)}
        rows={features}
        rowKey={(_, i) => i}
        remove={{
          header: "Remove",
          text: (f, i) => `Remove ${f.id || `feature ${i + 1}`}`,
          onRemove: (_, i) => setFeatures(features.filter((_, k) => k !== i)),
        }}
      />
      <button type="button" onClick={() => setFeatures([...features, { id: `feature-${features.length + 1}`, fulfills: [], measures: [] }])}>
        Add feature
      </button>
    </fieldset>
  );
}
