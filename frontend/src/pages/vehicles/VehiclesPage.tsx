/**
 * The vehicle registry for admins: the profiles the checks use for orders that name a vehicle
 * without carrying its profile. Each save that changes a profile is a new version; any two
 * versions can be compared field by field.
 */
import { type FormEvent, useEffect, useMemo, useState } from "react";

import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { trustedBehaviours } from "../../editor/pickers";
import { formatDateTime } from "../../format";
import { DataTable } from "../../components/DataTable";
import { type RegistryProfile, useSaveVehicle, useVehicles, useVehicleVersions } from "../../api/vehicles";
import { ProfileChanges } from "./ProfileChanges";
import { ProfileForm } from "./ProfileForm";
import { profileDiff } from "./profileDiff";

const TEMPLATE = {
  id: "new-vehicle",
  title: "",
  behaviors: ["transit"],
  features: [],
  envelope: {},
};

export function VehiclesPage() {
  const { data, error, isPending: loading } = useVehicles();
  const saveProfile = useSaveVehicle();
  const [editing, setEditing] = useState<string | null>(null);
  const [text, setText] = useState("");
  const [saveError, setSaveError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);
  const [history, setHistory] = useState<string | null>(null);

  useEffect(() => {
    document.title = "Vehicle registry · Countersign";
  }, []);

  const edit = (profile: RegistryProfile | null) => {
    setEditing(profile?.id ?? "");
    setText(JSON.stringify(profile ?? TEMPLATE, null, 2));
    setSaveError(null);
    setNotice(null);
  };

  // The form and the JSON box edit one profile: the text is the source, the form its reading.
  const formProfile = useMemo(() => {
    try {
      const parsed: unknown = JSON.parse(text);
      return typeof parsed === "object" && parsed !== null && !Array.isArray(parsed) ? (parsed as RegistryProfile & Record<string, unknown>) : null;
    } catch {
      return null;
    }
  }, [text]);

  const save = async (event: FormEvent) => {
    event.preventDefault();
    setSaveError(null);
    setNotice(null);
    let profile: RegistryProfile;
    try {
      profile = JSON.parse(text) as RegistryProfile;
    } catch (problem) {
      setSaveError(`The profile is not JSON: ${problem instanceof Error ? problem.message : String(problem)}`);
      return;
    }
    if (typeof profile !== "object" || profile === null || typeof profile.id !== "string" || !profile.id) {
      setSaveError("The profile needs an id.");
      return;
    }
    try {
      await saveProfile.mutateAsync(profile);
    } catch (problem) {
      setSaveError(problem);
      return;
    }
    setNotice(`Vehicle ${profile.id} saved.`);
    setEditing(null);
    setHistory(profile.id);
  };

  return (
    <section aria-labelledby="vehicles-title">
      <h1 id="vehicles-title" tabIndex={-1}>
        Vehicle registry
      </h1>
      <p>
        Orders that name a vehicle without its profile are checked against the profile here, and that profile is
        copied into the version, so an approval covers exactly the profile it was checked with.
      </p>
      <ErrorMessage error={error} />
      {notice && <Notice>{notice}</Notice>}
      {loading && !data ? (
        <Loading what="vehicles" />
      ) : (
        <DataTable
          caption="Vehicles in the registry"
          className="vehicles"
          rows={data ?? []}
          rowKey={(v) => v.id}
          empty="The registry has no vehicles yet."
          columns={[
            { header: "Vehicle", cell: (v) => <code>{v.id}</code> },
            { header: "Title", cell: (v) => v.title ?? "" },
            { header: "Trusted behaviours", cell: (v) => trustedBehaviours(v).join(", ") },
            {
              header: "Actions",
              className: "actions",
              cell: (v) => (
                <>
                  <button type="button" onClick={() => edit(v)}>
                    Edit {v.id}
                  </button>
                  <button type="button" onClick={() => setHistory(v.id)}>
                    Versions of {v.id}
                  </button>
                </>
              ),
            },
          ]}
        />
      )}
      <p>
        <button type="button" onClick={() => edit(null)}>
          New vehicle
        </button>
      </p>
      {editing !== null && (
        <form onSubmit={(e) => void save(e)} className="panel-box">
          <h2>{editing ? `Edit ${editing}` : "New vehicle"}</h2>
          {formProfile !== null ? (
            <ProfileForm profile={formProfile} fixedId={editing !== ""} onChange={(p) => setText(JSON.stringify(p, null, 2))} />
          ) : (
            <p className="hint">The JSON below does not read as a profile: the form shows it again once it does.</p>
          )}
          <label htmlFor="vehicle-profile-json">Vehicle profile (JSON)</label>
          <textarea
            id="vehicle-profile-json"
            rows={14}
            spellCheck={false}
            value={text}
            onChange={(e) => setText(e.target.value)}
          />
          <ErrorMessage error={saveError} />
          <p className="actions">
            <button type="submit">Save vehicle</button>
            <button type="button" onClick={() => setEditing(null)}>
              Cancel
            </button>
          </p>
        </form>
      )}
      {history && <VersionHistory key={history} id={history} />}
    </section>
  );
}

function VersionHistory({ id }: { id: string }) {
  const { data, error, isPending: loading } = useVehicleVersions(id);
  const [from, setFrom] = useState<number | null>(null);
  const [to, setTo] = useState<number | null>(null);
  if (loading && !data) return <Loading what={`versions of ${id}`} />;
  if (!data) return <ErrorMessage error={error} />;
  const newest = data[0]?.number ?? 1;
  const right = to ?? newest;
  const left = from ?? (data[1]?.number ?? newest);
  const profileOf = (n: number) => data.find((v) => v.number === n)?.profile ?? {};
  return (
    <section aria-labelledby="vehicle-versions-title">
      <h2 id="vehicle-versions-title">Versions of {id}</h2>
      <ol reversed className="vehicle-versions" data-testid="vehicle-versions">
        {data.map((v) => (
          <li key={v.number}>
            Version {v.number}, saved by {v.saved_by ?? "(before versions were kept)"} on{" "}
            <time dateTime={v.saved_at}>{formatDateTime(v.saved_at)}</time>
          </li>
        ))}
      </ol>
      <div className="pair">
        <span>
          <label htmlFor="vehicle-diff-from">Compare version</label>
          <select id="vehicle-diff-from" value={left} onChange={(e) => setFrom(Number(e.target.value))}>
            {data.map((v) => (
              <option key={v.number} value={v.number}>
                {v.number}
              </option>
            ))}
          </select>
        </span>
        <span>
          <label htmlFor="vehicle-diff-to">with version</label>
          <select id="vehicle-diff-to" value={right} onChange={(e) => setTo(Number(e.target.value))}>
            {data.map((v) => (
              <option key={v.number} value={v.number}>
                {v.number}
              </option>
            ))}
          </select>
        </span>
      </div>
      <h3>
        Changes from version {left} to version {right}
      </h3>
      <ProfileChanges changes={profileDiff(profileOf(left), profileOf(right))} testId="vehicle-diff" />
    </section>
  );
}
