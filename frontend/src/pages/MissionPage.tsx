import { useEffect, useState } from "react";

import { ApiError, EXPORT_FORMATS, exportHref, type MissionDetail, type Version } from "../api/client";
import {
  useCreateVersion,
  useDeleteMission,
  useMission,
  useMissionPaths,
  usePlainOrders,
  useReloadMission,
  useSaveDraft,
} from "../api/missions";
import { prefetchReport } from "../api/reportPrefetch";
import { useReport } from "../api/reports";
import { ChartPlanView } from "../components/ChartPlanView";
import { type Column, DataTable } from "../components/DataTable";
import type { Orders } from "../editor/graph";
import { FindingsTable } from "../components/FindingsTable";
import { Link } from "../components/Link";
import { PathCounts } from "../components/PathCounts";
import {
  currentCursor,
  firstPage,
  nextPage,
  Pager,
  previousPage,
} from "../components/Pager";
import { CheckBadge, ErrorMessage, Loading, Notice } from "../components/Status";
import { Tabs } from "../components/Tabs";
import { VehicleExports } from "../components/VehicleExports";
import { MissionStanding, MissionStatus } from "./MissionStanding";
import { formatDateTime, formatNumber, plural, shortDigest } from "../format";
import { navigate } from "../navigation";
import { missionHref } from "../router";
import { useCan, useSession } from "../session";
import { outcomeLetters, traceText } from "../trace";
import { SubmissionPanel } from "./approvals";
import { IntegrityWarning } from "./approvals/parts";
import { CampaignPanel } from "./campaigns/CampaignPanel";
import { RehearsalPanel } from "./RehearsalPage";

const TABS = [
  "orders", "findings", "paths", "plan", "versions", "rehearse", "edit", "editor",
] as const;

// The graph editor (React Flow, ELK) is a large module: loaded when an operator opens it. It is
// held in state rather than React.lazy: a suspended lazy component is revealed only after
// React's Suspense throttle (300 ms), which was a sixth of opening a large mission.
type EditorComponent = (typeof import("../editor/MissionEditor"))["default"];
let loadedEditor: EditorComponent | null = null;
function loadEditor(): Promise<EditorComponent> {
  return import("../editor/MissionEditor").then((m) => (loadedEditor = m.default));
}
type Tab = (typeof TABS)[number];

export function MissionPage({ id, tab }: { id: string; tab: string }) {
  const canEdit = useCan("editDraft");
  const canRehearse = ["operator", "supervisor"].includes(useSession().user.role);
  const { data: mission, error, isPending: loading } = useMission(id);
  const [MissionEditor, setMissionEditor] = useState<EditorComponent | null>(() => loadedEditor);
  // The editor's findings are asked for beside the mission, not after the editor mounted.
  const [editorReport] = useState(() => (canEdit && tab === "editor" ? prefetchReport(id) : null));
  const [editorError, setEditorError] = useState<unknown>(null);
  useEffect(() => {
    // Fetch the editor's code while the mission loads, not after (operators only).
    if (canEdit && tab === "editor" && !MissionEditor) {
      loadEditor().then((c) => setMissionEditor(() => c), setEditorError);
    }
  }, [canEdit, tab, MissionEditor]);
  const tabs = TABS.filter((t) => (t !== "edit" && t !== "editor") || canEdit);
  const selected: Tab = (tabs as readonly string[]).includes(tab) ? (tab as Tab) : "orders";

  useEffect(() => {
    document.title = `${mission?.title || id} · Countersign`;
  }, [mission?.title, id]);

  if (loading && !mission) return <Loading what="the mission" />;
  if (!mission) {
    return (
      <section>
        <h1 tabIndex={-1}>Mission {id}</h1>
        <ErrorMessage error={error ?? "The mission could not be loaded."} />
        <p>
          <Link href="/missions">Back to missions</Link>
        </p>
      </section>
    );
  }

  const labels: Record<Tab, string> = {
    orders: "Orders",
    findings:
      mission.ok === null || mission.ok === undefined
        ? "Findings"
        : `Findings (${(mission.errors ?? 0) + (mission.warnings ?? 0)})`,
    paths: "Paths",
    plan: "Plan view",
    versions: `Versions (${mission.versions.length})`,
    edit: "Edit orders",
    editor: "Graph editor",
    rehearse: "Rehearse",
  };

  return (
    <section aria-labelledby="mission-title">
      <p className="breadcrumb">
        <Link href="/missions">Missions</Link> / <code>{mission.id}</code>
      </p>
      <div className="page-head">
        <h1 id="mission-title" tabIndex={-1}>
          {mission.title || mission.id}
        </h1>
        <CheckBadge ok={mission.ok} errors={mission.errors} warnings={mission.warnings} />
      </div>
      {/* The status shown is the log's; a table that says otherwise is named. */}
      <IntegrityWarning problems={mission.integrity} />
      <dl className="facts">
        <div>
          <dt>Status</dt>
          <dd>
            <MissionStatus id={mission.id} status={mission.status} />
          </dd>
        </div>
        <div>
          <dt>Decisions</dt>
          <dd>
            <MissionStanding id={mission.id} status={mission.status} />
          </dd>
        </div>
        <div>
          <dt>Vehicle</dt>
          <dd>{mission.vehicle ?? "—"}</dd>
        </div>
        <div>
          <dt>Draft digest</dt>
          <dd>
            <code title={mission.draft_digest}>{shortDigest(mission.draft_digest)}</code>
          </dd>
        </div>
        <div>
          <dt>Revision</dt>
          <dd>{mission.revision}</dd>
        </div>
        <div>
          <dt>Updated</dt>
          <dd>
            <time dateTime={mission.updated_at}>{formatDateTime(mission.updated_at)}</time> by{" "}
            {mission.updated_by}
          </dd>
        </div>
      </dl>
      <nav className="exports" aria-label="Export the draft">
        <span>Export:</span>
        <ul>
          {EXPORT_FORMATS.map((f) => (
            <li key={f.format}>
              <a href={exportHref(mission.id, f.format)} download title={f.description}>
                {f.label}
              </a>
            </li>
          ))}
        </ul>
      </nav>
      {mission.import_findings && mission.import_findings.length > 0 && (
        <Notice>
          Import notes: {mission.import_findings.length} finding
          {mission.import_findings.length === 1 ? "" : "s"} from reading the file (see Findings).
        </Notice>
      )}
      <Tabs
        label="Mission views"
        tabs={tabs.map((t) => ({ id: t, label: labels[t] }))}
        selected={selected}
        onSelect={(t) => navigate(missionHref(mission.id, t), { replace: true })}
      >
        {selected === "orders" && <OrdersTab id={mission.id} digest={mission.draft_digest} />}
        {selected === "findings" && <FindingsTab mission={mission} />}
        {selected === "paths" && <PathsTab mission={mission} />}
        {selected === "plan" && <ChartPlanView orders={mission.orders} />}
        {selected === "versions" && <VersionsTab mission={mission} />}
        {selected === "rehearse" && <RehearsalPanel mission={mission} canRehearse={canRehearse} />}
        {selected === "edit" && canEdit && <EditTab mission={mission} />}
        {selected === "editor" && canEdit && (
          MissionEditor ? (
            <MissionEditor key={mission.id} mission={mission} report={editorReport} />
          ) : editorError ? (
            <ErrorMessage error={editorError} />
          ) : (
            <Loading what="the graph editor" />
          )
        )}
      </Tabs>
    </section>
  );
}

function OrdersTab({ id, digest }: { id: string; digest: string }) {
  const { data, error, isFetching: loading } = usePlainOrders(id, digest);
  return (
    <>
      <h2>Plain-language orders</h2>
      <ErrorMessage error={error} />
      {loading && !data ? (
        <Loading what="the orders" />
      ) : (
        <pre className="orders-text" data-testid="plain-orders">
          {data}
        </pre>
      )}
    </>
  );
}

function FindingsTab({ mission }: { mission: MissionDetail }) {
  const { data, error, isFetching: loading } = useReport(mission.id, mission.draft_digest);
  if (loading && !data) return <Loading what="the validation report" />;
  if (!data) return <ErrorMessage error={error} />;
  const errors = data.findings.filter((f) => f.severity === "error").length;
  return (
    <>
      <h2>Findings</h2>
      <p className={data.ok ? "verdict ok" : "verdict bad"} data-testid="verdict">
        {data.ok ? "The orders pass every check" : "The orders do not pass"}:{" "}
        {plural(errors, "error")}, {plural(data.findings.length - errors, "warning")}.
        {data.paths
          ? ` ${plural(data.paths.count, "path")} in all.`
          : " Paths cannot be counted until the structural errors are fixed."}
      </p>
      <FindingsTable findings={data.findings} caption="Findings of the draft's validation" />
      {data.costs && Object.keys(data.costs).length > 0 && (
        <>
          <h3>Costliest path</h3>
          <ul className="costs">
            {Object.entries(data.costs).map(([quantity, cost]) => (
              <li key={quantity}>
                <strong>{quantity}</strong>: {formatNumber(cost.worst)}
                {typeof cost.budget === "number" ? ` of a budget of ${formatNumber(cost.budget)}` : ""}
                {cost.path ? ` (${cost.path.goals.join(" → ")} → ${cost.path.terminal})` : ""}
                {cost.estimated_cost && cost.estimated_cost.length > 0
                  ? `; estimated for ${cost.estimated_cost.join(", ")}`
                  : ""}
                {cost.unknown_cost && cost.unknown_cost.length > 0
                  ? `; unknown for ${cost.unknown_cost.join(", ")}`
                  : ""}
              </li>
            ))}
          </ul>
        </>
      )}
    </>
  );
}

const PATHS_PER_PAGE = 20;

function PathsTab({ mission }: { mission: MissionDetail }) {
  const [pages, setPages] = useState(firstPage);
  const [open, setOpen] = useState<number | null>(null);
  const cursor = currentCursor(pages);
  const { data, error, isFetching: loading } = useMissionPaths(mission.id, mission.draft_digest, cursor ?? null, PATHS_PER_PAGE);

  if (loading && !data) return <Loading what="the paths" />;
  if (!data) {
    const status = error instanceof ApiError ? error.status : 0;
    return status === 409 ? (
      <>
        <h2>Paths</h2>
        <Notice>{(error as Error).message}</Notice>
      </>
    ) : (
      <ErrorMessage error={error} />
    );
  }
  const orders = mission.orders as Parameters<typeof traceText>[1];
  return (
    <>
      <h2>Paths</h2>
      <PathCounts count={data.count} byTerminal={data.by_terminal} testIdPrefix="paths-to-" />
      <ol className="paths" aria-busy={loading}>
        {data.items.map((p) => (
          <li key={p.index} value={p.index}>
            <div className="path-row">
              <span className="path-goals">
                {p.goals.map((g, i) => `${g} (${outcomeLetters([p.outcomes[i] ?? ""])})`).join(" → ")}{" "}
                → <strong>{p.terminal}</strong>
              </span>
              <button
                type="button"
                aria-expanded={open === p.index}
                aria-controls={`trace-${p.index}`}
                onClick={() => setOpen(open === p.index ? null : p.index)}
              >
                {open === p.index ? "Hide trace" : "Trace"}
                <span className="visually-hidden"> of path {p.index}</span>
              </button>
            </div>
            {open === p.index && (
              <pre id={`trace-${p.index}`} className="trace">
                {traceText(p, orders)}
              </pre>
            )}
          </li>
        ))}
      </ol>
      <Pager
        label="Path pages"
        page={pages.cursors.length}
        hasPrevious={pages.cursors.length > 1}
        hasNext={!!data.next_cursor}
        onPrevious={() => setPages(previousPage(pages))}
        onNext={() => data.next_cursor && setPages(nextPage(pages, data.next_cursor))}
      />
    </>
  );
}

function versionColumns(mission: string): Column<Version>[] {
  return [
    { header: "Version", cell: (v) => `v${v.number}` },
    { header: "Digest", cell: (v) => <code title={v.digest}>{shortDigest(v.digest)}</code> },
    { header: "Author", cell: (v) => v.author },
    { header: "Created", cell: (v) => <time dateTime={v.created_at}>{formatDateTime(v.created_at)}</time> },
    { header: "Vehicle files", cell: (v) => <VehicleExports mission={mission} version={v.number} /> },
  ];
}

function VersionsTab({ mission }: { mission: MissionDetail }) {
  const canVersion = useCan("createVersion");
  const createVersion = useCreateVersion(mission.id);
  const busy = createVersion.isPending;
  const created = createVersion.data?.number ?? null;
  const create = () => createVersion.mutate();

  const versions = [...mission.versions].sort((a, b) => b.number - a.number);
  return (
    <>
      <div className="page-head">
        <h2>Versions</h2>
        {canVersion && (
          <button type="button" className="primary" onClick={create} disabled={busy}>
            {busy ? "Creating…" : "Create version"}
          </button>
        )}
      </div>
      <p className="hint">
        A version is an immutable snapshot of the draft; supervisors review and approve versions.
      </p>
      <ErrorMessage error={createVersion.error} />
      {created !== null && <Notice>Version {created} created.</Notice>}
      <SubmissionPanel mission={mission.id} versions={mission.versions.map((v) => v.number)} />
      <CampaignPanel mission={mission.id} versions={mission.versions.map((v) => v.number)} />
      {versions.length === 0 ? (
        <p className="empty">No versions yet.</p>
      ) : (
        <DataTable
          caption="Versions, newest first"
          className="versions"
          columns={versionColumns(mission.id)}
          rows={versions}
          rowKey={(v) => v.number}
        />
      )}
    </>
  );
}

function EditTab({ mission }: { mission: MissionDetail }) {
  const canDelete = useCan("deleteDraft");
  const saveDraft = useSaveDraft(mission.id);
  const deleteMission = useDeleteMission(mission.id);
  const reload = useReloadMission(mission.id);
  const [text, setText] = useState(() => JSON.stringify(mission.orders, null, 2));
  const [error, setError] = useState<unknown>(null);
  const [conflict, setConflict] = useState(false);
  const [saved, setSaved] = useState(false);
  const busy = saveDraft.isPending;
  const [revision, setRevision] = useState(mission.revision);

  useEffect(() => {
    // A new revision arrived (our save, or a reload after a conflict): edit that one.
    if (mission.revision !== revision) {
      setRevision(mission.revision);
      setText(JSON.stringify(mission.orders, null, 2));
      setConflict(false);
    }
  }, [mission.revision, mission.orders, revision]);

  const save = async () => {
    setError(null);
    setSaved(false);
    setConflict(false);
    let orders: Orders;
    try {
      // Whatever the text says: the server reads and checks the orders (422 names the field).
      orders = JSON.parse(text) as Orders;
    } catch (e) {
      setError(`The orders are not valid JSON: ${(e as Error).message}`);
      return;
    }
    try {
      const answer = await saveDraft.mutateAsync({ revision: mission.revision, orders });
      if (answer.theirs) {
        setConflict(true);
        return;
      }
      setSaved(true);
    } catch (e) {
      setError(e);
    }
  };

  const remove = async () => {
    if (!window.confirm(`Delete mission ${mission.id}? This cannot be undone.`)) return;
    setError(null);
    try {
      await deleteMission.mutateAsync();
      navigate("/missions");
    } catch (e) {
      setError(e);
    }
  };

  return (
    <>
      <h2>Edit orders (JSON)</h2>
      <p className="hint">
        Edits the draft, revision {mission.revision}. If someone else saves first, nothing is
        overwritten: you are asked to reload.
      </p>
      <label htmlFor="orders-json" className="visually-hidden">
        Orders JSON
      </label>
      <textarea
        id="orders-json"
        className="code"
        spellCheck={false}
        rows={24}
        value={text}
        onChange={(e) => setText(e.target.value)}
      />
      <ErrorMessage error={error} />
      {conflict && (
        <p className="message error" role="alert">
          Someone else saved this draft first; nothing was overwritten. Copy your changes if you
          need them, then reload to edit the current draft.{" "}
          <button type="button" onClick={reload}>
            Reload
          </button>
        </p>
      )}
      {saved && <Notice>Draft saved.</Notice>}
      <div className="actions">
        <button type="button" className="primary" onClick={save} disabled={busy}>
          {busy ? "Saving…" : "Save draft"}
        </button>
        {canDelete && mission.versions.length === 0 && (
          <button type="button" className="danger" onClick={remove} disabled={deleteMission.isPending}>
            Delete mission
          </button>
        )}
      </div>
    </>
  );
}
