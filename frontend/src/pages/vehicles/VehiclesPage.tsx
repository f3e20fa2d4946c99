/**
 * The vehicle registry for admins: the profiles the checks use for orders that name a vehicle
 * without carrying its profile. Each save that changes a profile is a new version; any two
 * versions can be compared field by field.
 */
import { type FormEvent, useEffect, useMemo, useState } from "react";

import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { trustedBehaviours } from "../../editor/pickers";
import { formatDateTime } from "../../format";
import { useLoad } from "../../useLoad";
import { loadVehicles, loadVehicleVersions, type RegistryProfile, saveVehicle } from "./api";
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
  const { data, error, loading, reload } = useLoad(loadVehicles, []);
  const [editing, setEditing] = useState<string | null>(null);
  const [text, setText] = useState("");
  const [saveError, setSaveError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);
  const [history, setHistory] = useState<string | null>(null);
  const [saved, setSaved] = useState(0);

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
      await saveVehicle(profile);
    } catch (problem) {
      setSaveError(problem);
      return;
    }
    setNotice(`Vehicle ${profile.id} saved.`);
    setEditing(null);
    setHistory(profile.id);
    setSaved((n) => n + 1);
    reload();
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
        <table className="vehicles">
          <caption className="visually-hidden">Vehicles in the registry</caption>
          <thead>
            <tr>
              <th scope="col">Vehicle</th>
              <th scope="col">Title</th>
              <th scope="col">Trusted behaviours</th>
              <th scope="col">Actions</th>
            </tr>
          </thead>
          <tbody>
            {(data ?? []).length === 0 && (
              <tr>
                <td colSpan={4}>The registry has no vehicles yet.</td>
              </tr>
            )}
            {(data ?? []).map((v) => (
              <tr key={v.id}>
                <td>
                  <code>{v.id}</code>
                </td>
                <td>{v.title ?? ""}</td>
                <td>{trustedBehaviours(v).join(", ")}</td>
                <td className="actions">
                  <button type="button" onClick={() => edit(v)}>
                    Edit {v.id}
                  </button>
                  <button type="button" onClick={() => setHistory(v.id)}>
                    Versions of {v.id}
                  </button>
                </td>
              </tr>
            ))}
          </tbody>
        </table>
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
      {history && <VersionHistory key={`${history}:${saved}`} id={history} />}
    </section>
  );
}

function VersionHistory({ id }: { id: string }) {
  const { data, error, loading } = useLoad(() => loadVehicleVersions(id), [id]);
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
