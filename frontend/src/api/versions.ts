/** A mission's saved versions as a resource: the review, the printable document, the procedures
 * used, the vehicle export's standing and the fault reach, each keyed under its mission, so a
 * write to the mission (a submission, a decision, evidence attached) reaches them. */
import { useQuery } from "@tanstack/react-query";

import { api, type Schema, unwrap } from "./client";
import { missionKeys } from "./missions";

export type Review = Schema<"ReviewOut">;
export type ProcedureUses = Schema<"ProcedureUsesOut">;

export const versionKeys = {
  one: (mission: string, version: number) => [...missionKeys.one(mission), "versions", version] as const,
  review: (mission: string, version: number) => [...versionKeys.one(mission, version), "review"] as const,
  document: (mission: string, version: number) => [...versionKeys.one(mission, version), "document"] as const,
  procedures: (mission: string, version: number) => [...versionKeys.one(mission, version), "procedures"] as const,
  vehicleExport: (mission: string, version: number) => [...versionKeys.one(mission, version), "vehicle-export"] as const,
  faultReach: (mission: string, version: number, faults: readonly string[]) =>
    [...versionKeys.one(mission, version), "fault-reach", faults.join(",")] as const,
};

const versionPath = (mission: string, version: number) => ({ path: { mission_id: mission, number: version } });

export async function loadReview(mission: string, version: number): Promise<Review> {
  return unwrap(await api.GET("/api/missions/{mission_id}/versions/{number}/review", { params: versionPath(mission, version) }));
}

/** The review of a version; `version` null (nothing chosen yet) asks for nothing. */
export function useReview(mission: string, version: number | null) {
  return useQuery({
    queryKey: versionKeys.review(mission, version ?? 0),
    queryFn: () => loadReview(mission, version ?? 0),
    enabled: version !== null,
  });
}

export function useApprovalDocument(mission: string, version: number) {
  return useQuery({
    queryKey: versionKeys.document(mission, version),
    queryFn: async () =>
      unwrap(await api.GET("/api/missions/{mission_id}/versions/{number}/document", { params: versionPath(mission, version) })),
  });
}

export function useProcedureUses(mission: string, version: number) {
  return useQuery({
    queryKey: versionKeys.procedures(mission, version),
    queryFn: async (): Promise<ProcedureUses> =>
      unwrap(await api.GET("/api/missions/{mission_id}/versions/{number}/procedures", { params: versionPath(mission, version) })),
  });
}

/** Whether the version's vehicle export stands approved (asked of the IMC plan). */
export function useVehicleExportApproved(mission: string, version: number) {
  return useQuery({
    queryKey: versionKeys.vehicleExport(mission, version),
    queryFn: async () =>
      unwrap(
        await api.GET("/api/missions/{mission_id}/versions/{number}/vehicle/{format}", {
          params: { path: { mission_id: mission, number: version, format: "imc" } },
        }),
      ).approved,
  });
}

/** Which goals react to the chosen faults; none chosen asks for nothing. */
export function useFaultReach(mission: string, version: number, faults: readonly string[]) {
  return useQuery({
    queryKey: versionKeys.faultReach(mission, version, faults),
    queryFn: async () =>
      unwrap(
        await api.GET("/api/missions/{mission_id}/versions/{number}/fault-reach", {
          params: { ...versionPath(mission, version), query: { fault: [...faults] } },
        }),
      ),
    enabled: faults.length > 0,
  });
}
