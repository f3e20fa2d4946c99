/**
 * The mission's standing beside its status: the latest approved version and the latest
 * decision, each on its own ("v1 approved; v2 rejected"), so a later rejection or a pending
 * submission never hides which version stands approved.
 */
import { useStanding } from "../api/missions";
import { Link } from "../components/Link";
import { approvalHref } from "./approvals/api";
import { statusWords } from "./missionStatus";

function useStandingOf(id: string, status: string) {
  return useStanding(id, status).data;
}

/** The status cell: the status in words with what stands approved (missionStatus.ts). */
export function MissionStatus({ id, status }: { id: string; status: string }) {
  const data = useStandingOf(id, status);
  return (
    <span className={`status status-${status}`} data-testid="mission-status">
      {statusWords(status, data?.approved, data?.latest)}
    </span>
  );
}

export function MissionStanding({ id, status }: { id: string; status: string }) {
  const data = useStandingOf(id, status);
  if (!data) return null;
  const { approved, latest } = data;
  if (!approved && !latest) return <span data-testid="mission-standing">No version decided yet</span>;
  return (
    <span data-testid="mission-standing">
      {approved ? (
        <Link href={approvalHref(approved.record)}>v{approved.version} approved</Link>
      ) : (
        "no version approved"
      )}
      {latest && latest.record !== approved?.record && (
        <>
          {"; "}
          <Link href={approvalHref(latest.record)}>
            v{latest.version} {latest.decision}
          </Link>
        </>
      )}
    </span>
  );
}
