// The plan map's field layer (issue 31): the rally points of the plan (the mission's or the planner's
// proposal), and on request each flying UAV's geofence as the .plan export and the upload send it (the
// geoFence of GET /plans/{id}/exports/qgc: the convex inclusion polygon around everything it flies; the
// no-fly zones, its exclusions, are drawn by the plan already). Fences are fetched once per plan.
import L from 'leaflet';
import { api } from './api.ts';
import { uavColour } from './palette.ts';

interface QgcFence {
  geoFence?: { polygons?: { inclusion?: boolean; polygon?: [number, number][] }[] };
}

/** the inclusion polygons of each UAV of a plan, [lat, lon] */
export type Fences = { uav: string; index: number; polygons: [number, number][][]; exclusions: number }[];

const fenceCache = new Map<number, Promise<Fences>>();
/** a few shapes: SVG (the map's own renderer is a canvas), so each is an element of its own */
let svg: L.Renderer | null = null;

/** each UAV's fence from its .plan export (a UAV whose export is refused has none: left out) */
export function planFences(planId: number, uavs: string[]): Promise<Fences> {
  let p = fenceCache.get(planId);
  if (!p) {
    p = Promise.all(
      uavs.map(async (uav, index) => {
        try {
          const doc = await api.get<QgcFence>(`/plans/${planId}/exports/qgc?uav=${encodeURIComponent(uav)}`);
          const all = doc.geoFence?.polygons ?? [];
          const polygons = all.filter((q) => q.inclusion && Array.isArray(q.polygon)).map((q) => q.polygon as [number, number][]);
          return { uav, index, polygons, exclusions: all.filter((q) => !q.inclusion).length };
        } catch {
          return null;
        }
      }),
    ).then((r) => r.filter((x): x is Fences[number] => x !== null));
    // a failed fetch is tried again next time
    p.catch(() => fenceCache.delete(planId));
    fenceCache.set(planId, p);
  }
  return p;
}

/** the rally points and, with `fences`, the geofences, as one layer group */
export function fieldLayer(rally: [number, number][], fences: Fences | null): L.LayerGroup {
  const group = L.layerGroup();
  const renderer = (svg ??= L.svg({ padding: 0.5 }));
  rally.forEach(([lon, lat], k) =>
    L.circleMarker([lat, lon], { radius: 7, color: '#0a7d32', weight: 3, fillColor: '#fff', fillOpacity: 1, className: 'plan-rally', renderer })
      .bindTooltip(`Rally point ${k + 1}`)
      .addTo(group),
  );
  for (const f of fences ?? [])
    for (const ring of f.polygons)
      L.polygon(ring, { color: uavColour(f.index), weight: 2, dashArray: '2 6', fill: false, interactive: false, className: 'plan-fence', renderer }).addTo(group);
  return group;
}
