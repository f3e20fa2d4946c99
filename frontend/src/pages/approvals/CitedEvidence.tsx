/**
 * What the signature cites besides the orders (DESIGN.md "what a signature must
 * mean"): the rehearsal record and the rehearsal campaigns attached to the submission, shown to the
 * supervisor before signing. The decision form signs only a statement that cites exactly these.
 */
import { type Campaign, useCitedCampaignList } from "../../api/campaigns";
import { ErrorMessage } from "../../components/Status";
import { shortDigest } from "../../format";
import { CampaignResults } from "../campaigns/CampaignPanel";
import { CitedRehearsal } from "./RehearsalSummary";


export interface CitedCampaigns {
  campaigns: Campaign[];
  error: unknown;
  loading: boolean;
}

/** The finished campaigns attached to a submission, with their records' digests and results. */
export function useCitedCampaigns(submission: number | undefined): CitedCampaigns {
  const { data, error, isPending } = useCitedCampaignList(submission);
  // Nothing to ask for without a submission: not loading.
  const loading = submission !== undefined && isPending;
  return { campaigns: data ?? [], error, loading };
}

export function CitedEvidence({
  rehearsal,
  cited,
  titles,
}: {
  rehearsal: string | null | undefined;
  cited: CitedCampaigns;
  titles: ReadonlyMap<string, string>;
}) {
  return (
    <section aria-labelledby="cited-evidence-title" data-testid="cited-evidence">
      <h2 id="cited-evidence-title">Rehearsals your signature cites</h2>
      <div data-testid="review-rehearsal">
        {rehearsal ? <CitedRehearsal digest={rehearsal} titles={titles} /> : <p>Rehearsal record: none attached.</p>}
      </div>
      {cited.error ? <ErrorMessage error={cited.error} /> : null}
      {cited.campaigns.length === 0 ? (
        <p data-testid="review-campaigns">{cited.loading ? "Loading the attached campaigns…" : "Rehearsal campaigns: none attached."}</p>
      ) : (
        <div data-testid="review-campaigns">
          {cited.campaigns.map((c) => (
            <div key={c.id}>
              <p>
                Campaign <code>{c.id}</code>, record <code title={c.digest ?? ""}>{shortDigest(c.digest ?? "", 16)}</code>
              </p>
              {c.error ? <p className="error" role="alert">{c.error}</p> : null}
              {c.results ? <CampaignResults campaign={c} offer={false} /> : null}
            </div>
          ))}
        </div>
      )}
    </section>
  );
}
