/**
 * The printable approval document of one version: the server lays it out
 * (GET .../document, the same plain orders as `countersign export --format plain`); this page
 * shows it and prints only it (print CSS: `.printable`).
 */
import { useEffect } from "react";

import { Link } from "../../components/Link";
import { ErrorMessage, Loading } from "../../components/Status";
import { missionHref } from "../../router";
import { useApprovalDocument } from "../../api/versions";
import { reviewHref } from "./api";

export function DocumentPage({ mission, version }: { mission: string; version: number }) {
  const { data, error, isPending: loading } = useApprovalDocument(mission, version);
  useEffect(() => {
    document.title = `Approval document ${mission} v${version} · Countersign`;
  }, [mission, version]);
  const textHref = `/api/missions/${encodeURIComponent(mission)}/versions/${version}/document.txt`;
  return (
    <section aria-labelledby="document-title">
      <p className="actions no-print">
        <Link href={missionHref(mission)}>Mission {mission}</Link>
        <Link href={reviewHref(mission, version)}>Review of v{version}</Link>
        <a href={textHref} download>
          Download as text
        </a>
        <button type="button" className="primary" onClick={() => window.print()} disabled={!data}>
          Print
        </button>
      </p>
      <ErrorMessage error={error} />
      {loading && !data ? <Loading what="the approval document" /> : null}
      <article className="printable approval-document" data-testid="approval-document">
        <h1 id="document-title" tabIndex={-1}>
          Approval document: {mission} v{version}
        </h1>
        {data?.sections.map((s) => (
          <section key={s.heading} aria-label={s.heading} className="document-section">
            <h2>{s.heading}</h2>
            <pre className="orders-text">{s.text}</pre>
          </section>
        ))}
      </article>
    </section>
  );
}
