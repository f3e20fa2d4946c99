/**
 * MapLibre under the app's CSP: its worker is the package's own module, served by the app
 * (same origin, hashed asset), and the only Trusted Types policy it gets, `map-worker`, passes
 * exactly that script and refuses to create HTML, so no string a user typed can become markup
 * through the map (the attribution control, the one place MapLibre writes HTML, is off).
 */
import { setTrustedTypesPolicy, setWorkerUrl } from "maplibre-gl";
import workerAsset from "maplibre-gl/dist/maplibre-gl-worker.mjs?url";

let installed = false;

export function installMapPolicy(): void {
  if (installed) return;
  installed = true;
  const href = new URL(workerAsset, window.location.href).href;
  const tt = window.trustedTypes;
  if (tt) {
    const policy = tt.createPolicy("map-worker", {
      createScriptURL: (raw: string) => {
        const u = new URL(raw, window.location.href);
        if (u.origin !== window.location.origin || !/\/maplibre-gl-worker[-.\w]*\.mjs$/.test(u.pathname)) {
          throw new TypeError(`not the map worker: ${raw}`);
        }
        return u.href;
      },
    });
    setTrustedTypesPolicy({
      createScriptURL: (url: string) => policy.createScriptURL(url),
      createHTML: () => {
        throw new TypeError("the map writes no HTML");
      },
    });
  }
  setWorkerUrl(href);
}
