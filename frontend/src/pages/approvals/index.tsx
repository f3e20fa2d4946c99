/** The approval pages' entries in the app's main navigation (their routes are in routes.tsx). */
import { Link } from "../../components/Link";
import { PAGE_ROLES } from "./routes";

export { SubmissionPanel } from "./SubmissionPanel";

const LINKS: { page: "reviews" | "audit" | "keys"; href: string; label: string }[] = [
  { page: "reviews", href: "/reviews", label: "Reviews" },
  { page: "audit", href: "/audit", label: "Audit" },
  { page: "keys", href: "/keys", label: "Keys" },
];

export function ApprovalNavLinks({ role, current }: { role: string; current: string }) {
  return (
    <>
      {LINKS.filter((l) => PAGE_ROLES[l.page].includes(role)).map((l) => (
        <li key={l.page}>
          <Link href={l.href} aria-current={current === l.page ? "page" : undefined}>
            {l.label}
          </Link>
        </li>
      ))}
    </>
  );
}
