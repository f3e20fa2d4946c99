/** The approval pages as the app shell mounts them: nav links and the page switch. */
import type { ReactNode } from "react";

import { Link } from "../../components/Link";
import { ApprovalPage } from "./ApprovalPage";
import { AuditPage } from "./AuditPage";
import { DocumentPage } from "./DocumentPage";
import { KeysPage } from "./KeysPage";
import { ReviewPage } from "./ReviewPage";
import { ReviewsPage } from "./ReviewsPage";
import { type ApprovalRoute, PAGE_ROLES } from "./routes";

export { SubmissionPanel } from "./SubmissionPanel";
export { type ApprovalRoute, parseApprovalRoute } from "./routes";

const LINKS: { page: "reviews" | "audit" | "keys"; href: string; label: string }[] = [
  { page: "reviews", href: "/reviews", label: "Reviews" },
  { page: "audit", href: "/audit", label: "Audit" },
  { page: "keys", href: "/keys", label: "Keys" },
];

export function ApprovalNavLinks({ role, current }: { role: string; current: ApprovalRoute | null }) {
  const at = current?.page === "approval" ? "audit" : current?.page;
  return (
    <>
      {LINKS.filter((l) => PAGE_ROLES[l.page].includes(role)).map((l) => (
        <li key={l.page}>
          <Link href={l.href} aria-current={at === l.page ? "page" : undefined}>
            {l.label}
          </Link>
        </li>
      ))}
    </>
  );
}

export function ApprovalPages({ route, role, forbidden }: { route: ApprovalRoute; role: string; forbidden: ReactNode }) {
  if (!PAGE_ROLES[route.page].includes(role)) return <>{forbidden}</>;
  switch (route.page) {
    case "review":
      return <ReviewPage key={`${route.mission}/${route.version}`} mission={route.mission} version={route.version} />;
    case "document":
      return <DocumentPage key={`${route.mission}/${route.version}`} mission={route.mission} version={route.version} />;
    case "reviews":
      return <ReviewsPage />;
    case "keys":
      return <KeysPage />;
    case "audit":
      return <AuditPage />;
    case "approval":
      return <ApprovalPage key={route.id} id={route.id} />;
  }
}
