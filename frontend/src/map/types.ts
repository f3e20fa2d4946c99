/** What the chart draws and reports back, shared by the lazy wrapper and the map itself (this
 * module imports no MapLibre, so the main bundle never pulls the map in). */
import type { LatLon, MapArea, MapLeg } from "./features";

export interface MapTiles {
  /** A checked {z}/{x}/{y} template from the server's settings (map_tiles.py). */
  template: string;
  /** Shown as text beside the map, never as markup. */
  attribution: string;
}

export interface ChartMapProps {
  /** The accessible name of the map (e.g. "Chart of the areas"). */
  label: string;
  testId?: string;
  areas: readonly MapArea[];
  legs?: readonly MapLeg[];
  /** A planned route: points with labels (1, 2, ...). */
  route?: readonly { at: LatLon; label: string }[];
  /** Coastline segments of the server's land mask, (lat, lon) pairs. */
  coastline?: readonly (readonly (readonly number[])[])[];
  tiles?: MapTiles | null;
  /** The selected area, whose vertices are drawn as draggable handles when editing. */
  selected?: string | null;
  onSelect?: (id: string) => void;
  /** When set, a click on the map adds a vertex (latitude, longitude) there. */
  onAddVertex?: ((at: LatLon) => void) | null;
  onMoveVertex?: (area: string, index: number, at: LatLon) => void;
  /** The view is fitted again when this changes (not at every vertex edit). */
  fitKey: string;
  /** Label the legs (goal and outcome letter). */
  legLabels?: boolean;
}
