/** The vehicle registry's API calls, typed from the OpenAPI document (schema.d.ts). */
import { api, type Schema, unwrap } from "../../api/client";

export type VehicleVersion = Schema<"VehicleVersionOut">;
export type RegistryProfile = Schema<"Vehicle">;

export async function loadVehicles(): Promise<RegistryProfile[]> {
  return unwrap(await api.GET("/api/vehicles")) ?? [];
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
