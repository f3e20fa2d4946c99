/**
 * The editor's import controls: replace the draft with orders read from a JSON, AVCL XML or
 * MEO Turtle file (the server reads it and stores nothing; the editor then saves it as an
 * ordinary, undoable edit with If-Match), and start a new mission from a built-in example.
 */
import { type FormEvent, useEffect, useId, useRef, useState } from "react";

import { api, type Schema, unwrap } from "../api/client";
import { useCreateMission } from "../api/missions";
import { ErrorMessage } from "../components/Status";
import { navigate } from "../navigation";
import { missionHref } from "../router";

export function ImportMenu({ onImport, busy }: { onImport: (file: File) => Promise<void>; busy: boolean }) {
  const inputId = useId();
  const [error, setError] = useState<unknown>(null);
  return (
    <details className="import-menu">
      <summary>Import…</summary>
      <div className="menu-body">
        <label htmlFor={inputId}>Replace this draft with a file (.json, .xml, .ttl)</label>
        <input
          id={inputId}
          type="file"
          data-testid="editor-import-file"
          disabled={busy}
          accept=".json,.xml,.avcl,.ttl,.turtle,application/json,application/xml,text/xml,text/turtle"
          onChange={(e) => {
            const file = e.target.files?.[0];
            e.target.value = "";
            if (!file) return;
            setError(null);
            onImport(file).catch(setError);
          }}
        />
        <p className="hint">The goals, constraints and norms of the file replace this draft; Undo brings the draft back.</p>
        <ErrorMessage error={error} />
      </div>
    </details>
  );
}

type Example = Schema<"ExampleOut">;

/** "New from example": a built-in example saved as a new mission, opened in the editor. */
// Length: one form: the example, its new id and title, with the create request's states.
export function NewFromExample() {
  const [examples, setExamples] = useState<Example[] | null>(null);
  const [name, setName] = useState("");
  const [id, setId] = useState("");
  const createMission = useCreateMission();
  const [error, setError] = useState<unknown>(null);
  const [open, setOpen] = useState(false);
  const touched = useRef(false);
  useEffect(() => {
    if (!open || examples) return;
    api
      .GET("/api/examples")
      .then((x) => {
        const list = unwrap(x);
        setExamples(list);
        if (list[0]) {
          setName(list[0].name);
          if (!touched.current) setId(`${list[0].id}-copy`);
        }
      })
      .catch(setError);
  }, [open, examples]);
  const create = async (event: FormEvent) => {
    event.preventDefault();
    const newId = id.trim();
    if (!name || !newId) {
      setError("Choose an example and give the new mission an id.");
      return;
    }
    setError(null);
    try {
      const orders = unwrap(await api.GET("/api/examples/{name}", { params: { path: { name } } }));
      const mission = await createMission.mutateAsync({ ...orders, id: newId });
      navigate(missionHref(mission.id, "editor"));
    } catch (e) {
      setError(e);
    }
  };
  const busy = createMission.isPending;
  return (
    <details className="import-menu" onToggle={(e) => setOpen((e.target as HTMLDetailsElement).open)}>
      <summary>New from example…</summary>
      <form className="menu-body" onSubmit={(e) => void create(e)} aria-label="New mission from a built-in example">
        <label htmlFor="example-name">Example</label>
        <select
          id="example-name"
          value={name}
          onChange={(e) => {
            setName(e.target.value);
            const chosen = examples?.find((x) => x.name === e.target.value);
            if (chosen && !touched.current) setId(`${chosen.id}-copy`);
          }}
        >
          {(examples ?? []).map((x) => (
            <option key={x.name} value={x.name}>
              {x.title || x.name} ({x.goals} goals)
            </option>
          ))}
        </select>
        <label htmlFor="example-id">New mission id</label>
        <input
          id="example-id"
          value={id}
          onChange={(e) => {
            touched.current = true;
            setId(e.target.value);
          }}
        />
        <button type="submit" disabled={busy || !examples}>
          {busy ? "Creating…" : "Create and open"}
        </button>
        <ErrorMessage error={error} />
      </form>
    </details>
  );
}
