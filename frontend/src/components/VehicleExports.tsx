/**
 * Vehicle files of one version: IMC plan and MOOS-IvP helm files as plain download
 * links (same origin, the session cookie goes along), and on request the notes naming what
 * each format cannot carry. Notes are server text: rendered as React text, never markup.
 */
import { useState } from "react";

import { api, unwrap } from "../api/client";
import { useVehicleExportApproved } from "../api/versions";
import type { components } from "../api/schema";
import { ErrorMessage } from "./Status";
import "./vehicleExports.css";

type VehicleExport = components["schemas"]["VehicleExportOut"];
type VehicleFormat = VehicleExport["format"];

const FILES: { format: VehicleFormat; suffix: string; label: string }[] = [
  { format: "imc", suffix: "imc", label: "IMC plan" },
  { format: "moos", suffix: "bhv", label: "MOOS .bhv" },
  { format: "moos", suffix: "moos", label: ".moos" },
];

export function vehicleFileHref(mission: string, version: number, format: VehicleFormat,
                                name: string): string {
  const m = encodeURIComponent(mission);
  return `/api/missions/${m}/versions/${version}/vehicle/${format}/${encodeURIComponent(name)}`;
}

/** The signed package of an approved version (409 problem when it has no standing approval). */
export function packageHref(mission: string, version: number): string {
  return `/api/missions/${encodeURIComponent(mission)}/versions/${version}/package`;
}

export function VehicleExports({ mission, version }: { mission: string; version: number }) {
  const [notes, setNotes] = useState<VehicleExport[] | null>(null);
  const [error, setError] = useState<unknown>(null);
  // The package exists only for a version with a standing approval (the route answers 409
  // otherwise): ask the export listing, which says so, before offering the link.
  const standing = useVehicleExportApproved(mission, version);

  async function loadNotes() {
    setError(null);
    try {
      const listings = await Promise.all(
        (["imc", "moos"] as const).map(async (format) =>
          unwrap(await api.GET("/api/missions/{mission_id}/versions/{number}/vehicle/{format}", {
            params: { path: { mission_id: mission, number: version, format } },
          })),
        ),
      );
      setNotes(listings);
    } catch (e) {
      setError(e);
    }
  }

  return (
    <span className="vehicle-exports">
      {FILES.map((f) => (
        <a key={f.suffix} href={vehicleFileHref(mission, version, f.format, `${mission}.${f.suffix}`)}
           download>
          {f.label}
        </a>
      ))}{" "}
      {standing.data === true ? (
        <a href={packageHref(mission, version)} download data-testid="approved-package"
           title="approved package: orders, vehicle files, envelope, receipt, proof, checkpoint">
          Approved package
        </a>
      ) : standing.data === false ? (
        <span className="hint" data-testid="no-package">no package: v{version} is not approved</span>
      ) : null}{" "}
      {notes === null ? (
        <button type="button" className="link" onClick={() => void loadNotes()}>
          What they cannot carry
        </button>
      ) : (
        <ul className="export-notes">
          {notes.flatMap((listing) =>
            listing.notes.map((n, i) => (
              <li key={`${listing.format}-${i}`}>
                <strong>{listing.format.toUpperCase()}</strong> <code>{n.code}</code>{" "}
                <code>{n.path}</code>: {n.message}
              </li>
            )),
          )}
        </ul>
      )}
      {error !== null && <ErrorMessage error={error} />}
    </span>
  );
}
