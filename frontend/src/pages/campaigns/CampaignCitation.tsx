/**
 * The campaigns a submission cites, on the Versions tab beside its rehearsal
 * record: what is attached, and for the submitting operator while it awaits a decision, the
 * finished campaigns of exactly this version with an Attach button. Campaigns of other versions
 * or not yet finished are not offered (the server refuses them too: 409).
 */
import { useState } from "react";

import type { Schema } from "../../api/client";
import { useAttachCampaign, useAttachedCampaigns, useMissionCampaigns } from "../../api/campaigns";
import { ErrorMessage } from "../../components/Status";
import { shortDigest } from "../../format";

type Submission = Schema<"SubmissionOut">;

export function CampaignCitation({
  mission,
  version,
  submission,
  mayAttach,
  onAttached,
}: {
  mission: string;
  version: number;
  submission: Submission;
  mayAttach: boolean;
  onAttached: (message: string) => void;
}) {
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<unknown>(null);
  const attachedQuery = useAttachedCampaigns(submission.id);
  const campaignsQuery = useMissionCampaigns(mission, { enabled: mayAttach });
  const ready = attachedQuery.data && (!mayAttach || campaignsQuery.data);
  const data = ready ? { attached: attachedQuery.data ?? [], campaigns: mayAttach ? (campaignsQuery.data ?? []) : [] } : undefined;
  const loadError = attachedQuery.error ?? campaignsQuery.error;
  const attachCampaign = useAttachCampaign(mission, submission.id);
  const attached = new Set((data?.attached ?? []).map((a) => a.campaign));
  const offered = (data?.campaigns ?? []).filter((c) => c.version === version && c.state === "finished" && !attached.has(c.id));
  const attach = async (campaign: string) => {
    setBusy(true);
    setError(null);
    try {
      await attachCampaign.mutateAsync(campaign);
      onAttached(`Campaign ${campaign} attached to submission ${submission.id}.`);
    } catch (e) {
      setError(e);
    } finally {
      setBusy(false);
    }
  };
  return (
    <div className="campaign-citation" data-testid="campaign-citation">
      <p data-testid="cited-campaigns">
        Rehearsal campaigns:{" "}
        {data && data.attached.length > 0
          ? data.attached.map((a, i) => (
              <span key={a.campaign}>
                {i > 0 && ", "}
                <code>{a.campaign}</code> (record <code title={a.digest}>{shortDigest(a.digest, 8)}</code>)
              </span>
            ))
          : "none attached"}
      </p>
      {mayAttach && data && (
        offered.length === 0 ? (
          <p className="hint">
            No other finished campaign of v{version} to attach: start one under Rehearsal campaigns below, then attach it here.
          </p>
        ) : (
          <ul className="campaign-offers">
            {offered.map((c) => (
              <li key={c.id}>
                <code>{c.id}</code>: {c.simulations} simulations, {c.spec.faults.join(", ")} at {c.spec.goals.join(", ")}{" "}
                <button type="button" disabled={busy} onClick={() => void attach(c.id)} aria-label={`Attach campaign ${c.id}`}>
                  Attach
                </button>
              </li>
            ))}
          </ul>
        )
      )}
      <ErrorMessage error={error ?? loadError} />
    </div>
  );
}
