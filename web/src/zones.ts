// The area and its no-fly zones look the same in every tab (issue 29, defect 9): the area outlined in
// dark grey, no-fly zones red with a dashed outline; each map names them in a legend.
import type { PathsGeoJson } from './plan-geometry.ts';

export const AREA_STROKE = '#404040';
export const AREA_FILL = '#f2f2ed';
export const NFZ_STROKE = '#b31a1a';
export const NFZ_FILL = '#d93333';
export const NFZ_FILL_OPACITY = 0.3;

/** The legend's swatches for the area and the no-fly zones (HTML, no user text). */
export function zoneLegendHtml(): string {
  return (
    `<span class="zone-key"><span class="zone-swatch" style="border-color:${AREA_STROKE};background:${AREA_FILL}"></span>area</span>` +
    `<span class="zone-key" data-testid="legend-nfz"><span class="zone-swatch zone-swatch-nfz" style="border-color:${NFZ_STROKE};background:${NFZ_FILL}4d"></span>no-fly zone</span>`
  );
}

/** The area's and no-fly zones' rings ([lat, lon]) from a plan's paths.geojson. */
export function zoneRings(paths: PathsGeoJson): { area: [number, number][][][]; nfz: [number, number][][][] } {
  const area: [number, number][][][] = [];
  const nfz: [number, number][][][] = [];
  for (const f of paths.features) {
    const role = f.properties?.role;
    if (!role || f.geometry?.type !== 'Polygon') continue;
    const rings = (f.geometry.coordinates as number[][][]).map((r) => r.filter((p) => p.length >= 2).map((p) => [p[1], p[0]] as [number, number]));
    (role === 'no_fly_zone' ? nfz : area).push(rings);
  }
  return { area, nfz };
}
