/** The vehicle registry's API calls, typed from the OpenAPI document (schema.d.ts). */
import { type QueryClient, useMutation, useQuery, useQueryClient } from "@tanstack/react-query";

import { api, type Schema, unwrap } from "./client";
import { missionsChanged } from "./missions";

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

export const vehicleKeys = {
  all: ["vehicles"] as const,
  versions: (id: string) => ["vehicles", id, "versions"] as const,
  registry: (id: string) => ["vehicles", id, "registry"] as const,
};

export function useVehicles() {
  return useQuery({ queryKey: vehicleKeys.all, queryFn: loadVehicles });
}

export function useVehicleVersions(id: string) {
  return useQuery({ queryKey: vehicleKeys.versions(id), queryFn: () => loadVehicleVersions(id) });
}

/** The registry's versions of the vehicle `id` names (none when no id or the registry lacks it). */
export function useRegistryVersions(id: string | undefined) {
  return useQuery({
    queryKey: vehicleKeys.registry(id ?? ""),
    queryFn: () => registryVersions(id ?? ""),
    enabled: Boolean(id),
  });
}

/** A saved profile is a new version, and the drafts that use it are checked again. */
export function vehicleSaved(client: QueryClient): Promise<unknown> {
  return Promise.all([client.invalidateQueries({ queryKey: vehicleKeys.all }), missionsChanged(client)]);
}

/** Register a vehicle or save a new version of its profile. */
export function saveVehicleMutation(client: QueryClient) {
  return { mutationFn: saveVehicle, onSuccess: () => vehicleSaved(client) };
}

export function useSaveVehicle() {
  return useMutation(saveVehicleMutation(useQueryClient()));
}
