import { type FormEvent, useEffect, useRef, useState } from "react";

import { useCreateMission, useImportMission } from "../api/missions";
import { ErrorMessage } from "../components/Status";
import type { Orders } from "../editor/graph";
import { navigate } from "../navigation";
import { missionHref } from "../router";
import { contentTypeFor } from "../upload";
import { NewMissionVehicle } from "./NewMissionVehicle";

export function ImportPage() {
  const [file, setFile] = useState<File | null>(null);
  const [pasted, setPasted] = useState("");
  const [error, setError] = useState<unknown>(null);
  const importMission = useImportMission();
  const createMission = useCreateMission();
  const busy = importMission.isPending || createMission.isPending;
  const [newId, setNewId] = useState("");
  const [newTitle, setNewTitle] = useState("");
  const [newVehicle, setNewVehicle] = useState("");
  const fileRef = useRef<HTMLInputElement>(null);

  useEffect(() => {
    document.title = "Import · Countersign";
  }, []);

  const upload = async (body: string | Blob, contentType: string) => {
    setError(null);
    try {
      const mission = await importMission.mutateAsync({ body, contentType });
      navigate(missionHref(mission.id, "findings"));
    } catch (e) {
      setError(e);
    }
  };

  const submitFile = (event: FormEvent) => {
    event.preventDefault();
    if (!file) {
      setError("Choose a file first.");
      fileRef.current?.focus();
      return;
    }
    void upload(file, contentTypeFor(file.name, file.type));
  };

  const submitEmpty = async (event: FormEvent) => {
    event.preventDefault();
    const id = newId.trim();
    if (!id) {
      setError("Give the new mission an id.");
      return;
    }
    setError(null);
    try {
      // An empty draft: no goals yet, the default terminals; the graph editor takes it from here.
      const orders: Orders = {
        format: "countersign.orders/1",
        id,
        title: newTitle.trim(),
        goals: [],
        terminals: [
          { id: "COMPLETE", kind: "complete", title: "Mission complete" },
          { id: "ABORT", kind: "abort", title: "Mission abort" },
        ],
      };
      if (newVehicle.trim()) orders.vehicle = newVehicle.trim();
      const mission = await createMission.mutateAsync(orders);
      navigate(missionHref(mission.id, "editor"));
    } catch (e) {
      setError(e);
    }
  };

  const submitText = (event: FormEvent) => {
    event.preventDefault();
    const text = pasted.trim();
    if (!text) {
      setError("Paste orders first.");
      return;
    }
    void upload(text, contentTypeFor("", "", text));
  };

  return (
    <section aria-labelledby="import-title">
      <h1 id="import-title" tabIndex={-1}>
        Import or create a mission
      </h1>
      <p className="hint">
        A new mission starts as a draft from orders in <code>countersign.orders/1</code> JSON, AVCL
        XML (NPS AUV Workbench) or MEO Turtle. It is validated at once.
      </p>
      <ErrorMessage error={error} />
      <form className="card" onSubmit={(e) => void submitEmpty(e)} aria-labelledby="new-title">
        <h2 id="new-title">Start an empty mission</h2>
        <label htmlFor="new-id">Mission id</label>
        <input id="new-id" value={newId} onChange={(e) => setNewId(e.target.value)} />
        <label htmlFor="new-mission-title">Title</label>
        <input id="new-mission-title" value={newTitle} onChange={(e) => setNewTitle(e.target.value)} />
        <NewMissionVehicle value={newVehicle} onChange={setNewVehicle} />
        <button type="submit" className="primary" disabled={busy}>
          Create empty mission
        </button>
      </form>
      <form className="card" onSubmit={submitFile} aria-labelledby="upload-title">
        <h2 id="upload-title">Upload a file</h2>
        <label htmlFor="import-file">Orders file (.json, .xml, .ttl)</label>
        <input
          id="import-file"
          ref={fileRef}
          type="file"
          accept=".json,.xml,.avcl,.ttl,.turtle,application/json,application/xml,text/xml,text/turtle"
          onChange={(e) => setFile(e.target.files?.[0] ?? null)}
        />
        <button type="submit" className="primary" disabled={busy}>
          {busy ? "Importing…" : "Import file"}
        </button>
      </form>
      <form className="card" onSubmit={submitText} aria-labelledby="paste-title">
        <h2 id="paste-title">Or paste orders</h2>
        <label htmlFor="import-text">Orders (JSON, AVCL XML or Turtle)</label>
        <textarea
          id="import-text"
          className="code"
          rows={12}
          spellCheck={false}
          value={pasted}
          onChange={(e) => setPasted(e.target.value)}
        />
        <button type="submit" disabled={busy}>
          Create mission
        </button>
      </form>
    </section>
  );
}
