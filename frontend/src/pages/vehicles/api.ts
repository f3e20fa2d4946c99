/** The vehicle registry's calls, kept at this address for the graph editor (src/api/vehicles.ts). */
export * from "../../api/vehicles";
