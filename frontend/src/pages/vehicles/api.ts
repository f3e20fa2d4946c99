/** The vehicle registry's API calls, typed from the OpenAPI document (schema.d.ts). */
import { api, unwrap, type paths } from "../../api/client";

type JsonBody<R> = R extends { content: { "application/json": infer B } } ? B : never;

export type VehicleVersion = JsonBody<
  paths["/api/vehicles/{vehicle_id}/versions"]["get"]["responses"][200]
>[number];
export type RegistryProfile = Record<string, unknown> & { id: string; title?: string; behaviors?: string[] };

export async function loadVehicles(): Promise<RegistryProfile[]> {
  return (unwrap(await api.GET("/api/vehicles")) as RegistryProfile[]) ?? [];
}

export async function loadVehicleVersions(id: string): Promise<VehicleVersion[]> {
  return unwrap(await api.GET("/api/vehicles/{vehicle_id}/versions", { params: { path: { vehicle_id: id } } }));
}

/** The registry's versions of a vehicle, or none when the registry does not know it. */
export async function registryVersions(id: string): Promise<VehicleVersion[]> {
  const result = await api.GET("/api/vehicles/{vehicle_id}/versions", { params: { path: { vehicle_id: id } } });
  if (result.response.status === 404) return [];
  return unwrap(result);
}

export async function saveVehicle(profile: RegistryProfile): Promise<void> {
  unwrap(
    await api.PUT("/api/vehicles/{vehicle_id}", {
      params: { path: { vehicle_id: profile.id } },
      body: profile as never,
    }),
  );
}
