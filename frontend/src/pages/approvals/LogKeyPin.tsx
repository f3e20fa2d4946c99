/**
 * The log key pinned in this browser (trust on first use, per server origin, in localStorage):
 * the key the server presents, with its fingerprint and key id, an explicit "pin this key"
 * confirmation, a form to enter the published key instead, and a way to forget the pin.
 * The pin check itself (crypto/logkey.ts) joins the verification's checks.
 */
import { type FormEvent, useState } from "react";

import { ErrorMessage } from "../../components/Status";
import { fingerprint, serverName } from "../../crypto/keystore";
import {
  comparePin,
  forgetPin,
  type LogKey,
  loadPin,
  type PinState,
  type PinStorage,
  pinLogKey,
} from "../../crypto/logkey";
import { formatDateTime } from "../../format";
import { useQuery } from "@tanstack/react-query";

function browserStorage(): PinStorage {
  try {
    if (typeof window !== "undefined" && window.localStorage) return window.localStorage;
  } catch {
    // storage disabled: fall through
  }
  throw new Error("This browser keeps no local storage for this site, so no log key can be pinned.");
}

export interface LogKeyPin {
  state: PinState | undefined;
  error: unknown;
  reload: () => void;
}

/** The pin state for the key the server presents; reloads after the pin changes. */
export function useLogKeyPin(presentedKey: string): LogKeyPin {
  // The pin lives in this browser's storage, not on the server: read through TanStack Query
  // only for one way of loading; `reload` reads it again after the user changed it.
  const { data, error, refetch } = useQuery({
    queryKey: ["log-key-pin", serverName(), presentedKey],
    queryFn: async () => comparePin(await loadPin(browserStorage(), serverName()), presentedKey),
    retry: false,
  });
  return { state: data, error, reload: () => void refetch() };
}

function KeyFacts({ what, logKey, testId }: { what: string; logKey: LogKey; testId: string }) {
  return (
    <div data-testid={testId}>
      <dt>{what}</dt>
      <dd>
        <code className="fingerprint">{fingerprint(logKey.keyId)}</code>
        <br />
        <span className="hint">
          key id <code className="key-id">{logKey.keyId}</code>, public key <code>{logKey.publicKey}</code>
        </span>
      </dd>
    </div>
  );
}

export function LogKeyPanel({ pin }: { pin: LogKeyPin }) {
  const [confirming, setConfirming] = useState(false);
  const [entered, setEntered] = useState("");
  const [error, setError] = useState<unknown>(null);
  const state = pin.state;
  const origin = serverName();

  const change = async (work: () => Promise<unknown> | void) => {
    setError(null);
    try {
      await work();
      setConfirming(false);
      pin.reload();
    } catch (e) {
      setError(e);
    }
  };
  const pinPresented = () =>
    state && state.kind !== "unusable" && change(() => pinLogKey(browserStorage(), origin, state.presented.publicKey, "first use"));
  const pinEntered = (event: FormEvent) => {
    event.preventDefault();
    void change(async () => {
      await pinLogKey(browserStorage(), origin, entered, "entered");
      setEntered("");
    });
  };
  const forget = () => void change(() => forgetPin(browserStorage(), origin));

  return (
    <section className="log-key" aria-labelledby="log-key-title" data-testid="log-key">
      <h3 id="log-key-title">Log key</h3>
      <ErrorMessage error={pin.error} />
      {state?.kind === "unusable" && <p className="verdict bad">{state.problem}</p>}
      {state && state.kind !== "unusable" && (
        <>
          <p data-testid="log-key-state" className={state.kind === "differs" ? "verdict bad" : undefined}>
            {state.kind === "unpinned"
              ? "No log key is pinned in this browser for this server: the checks above trust the key the server sent. Compare it with the log key your administrator published, then pin it; from then on the verification fails if the server presents another key."
              : state.kind === "matches"
                ? `The server presents the log key pinned in this browser${state.pinned.pinnedAt ? ` on ${formatDateTime(state.pinned.pinnedAt)}` : ""} (${state.pinned.source === "entered" ? "entered by hand" : "pinned on first use"}).`
                : "The server presents a different log key from the one pinned in this browser. Do not trust these checkpoints until you know why the key changed."}
          </p>
          <dl className="facts">
            <KeyFacts what="Presented by the server" logKey={state.presented} testId="log-key-presented" />
            {state.kind !== "unpinned" && <KeyFacts what="Pinned in this browser" logKey={state.pinned} testId="log-key-pinned" />}
          </dl>
          {state.kind !== "matches" &&
            (confirming ? (
              <div className="card confirm" role="group" aria-labelledby="pin-confirm-text">
                <p id="pin-confirm-text">
                  Pin log key <code>{fingerprint(state.presented.keyId)}</code> for {origin}? Only if its key id matches the
                  published log key (the key <code>countersign audit verify --log-key</code> takes).
                  {state.kind === "differs" && " This replaces the key pinned before."}
                </p>
                <div className="actions">
                  <button type="button" className="primary" onClick={() => void pinPresented()}>
                    Confirm: pin this key
                  </button>
                  <button type="button" onClick={() => setConfirming(false)}>
                    Cancel
                  </button>
                </div>
              </div>
            ) : (
              <p className="actions">
                <button type="button" onClick={() => setConfirming(true)}>
                  {state.kind === "differs" ? "Pin the server's key instead…" : "Pin this key…"}
                </button>
              </p>
            ))}
        </>
      )}
      <details>
        <summary>Enter the published log key</summary>
        <form onSubmit={pinEntered} aria-label="Pin a log key entered by hand">
          <label htmlFor="log-key-entered">Expected log key (base64 of the raw key, or a PEM public key)</label>
          <textarea id="log-key-entered" rows={3} value={entered} maxLength={1000} onChange={(e) => setEntered(e.target.value)} />
          <div className="actions">
            <button type="submit" disabled={!entered.trim()}>
              Pin entered key
            </button>
            {state && state.kind !== "unpinned" && (
              <button type="button" onClick={forget}>
                Forget the pinned key
              </button>
            )}
          </div>
        </form>
      </details>
      <ErrorMessage error={error} />
    </section>
  );
}
