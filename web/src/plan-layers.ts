// A plan on a Leaflet map: each UAV's region shaded and its path in its colour (the CLI's palette),
// transit legs dashed, start and return points, and waypoint numbers once zoomed in (only those in
// view, so that long paths stay smooth). Paths use the map's canvas renderer and Leaflet's
// per-zoom simplification (smoothFactor).
import L from 'leaflet';
import { uavColour } from './palette.ts';

type Position = number[]; // [lon, lat]

export interface PlanJson {
  origin?: Position;
  uavs: { id: string; region?: { type: string; coordinates: Position[][][] }; start?: Position; regions?: number }[];
  cost?: { batteries_per_uav?: number; uavs?: { batteries?: number; flight_duration_min?: number }[] };
  coverage?: { uavs?: { id: string; poc?: number; pooc?: number }[] };
  [k: string]: unknown;
}

export interface PathsGeoJson {
  type: 'FeatureCollection';
  features: {
    type: 'Feature';
    properties: { kind?: string; uav?: string; part?: number; role?: string; index?: number };
    geometry: { type: string; coordinates: unknown };
  }[];
}

/** Zoom from which waypoint numbers are shown. */
export const LABEL_ZOOM = 17;
/** At most this many numbers at a time (the ones in view). */
const MAX_LABELS = 400;
/** Path vertices per polyline piece. */
const CHUNK = 4000;

const ll = (p: Position): L.LatLngTuple => [p[1], p[0]];

export interface DrawnPlan {
  group: L.LayerGroup;
  bounds: L.LatLngBounds | null;
  /** per UAV id: regions (polygons) and path parts drawn */
  counts: Map<string, { colour: string; polygons: number; paths: number; waypoints: number }>;
  remove(): void;
}

export function drawPlan(map: L.Map, plan: PlanJson, paths: PathsGeoJson, withLabels = true): DrawnPlan {
  const group = L.layerGroup();
  const bounds = L.latLngBounds([]);
  const index = new Map<string, number>();
  plan.uavs.forEach((u, i) => index.set(u.id, i));
  const counts: DrawnPlan['counts'] = new Map();
  for (const [id, i] of index) counts.set(id, { colour: uavColour(i), polygons: 0, paths: 0, waypoints: 0 });

  // the area and its no-fly zones
  for (const f of paths.features) {
    if (!f.properties.role || f.geometry.type !== 'Polygon') continue;
    const rings = (f.geometry.coordinates as Position[][]).map((r) => r.map(ll));
    const nfz = f.properties.role === 'no_fly_zone';
    L.polygon(rings, {
      color: nfz ? '#222' : '#555',
      weight: nfz ? 1.5 : 1.5,
      dashArray: nfz ? '4 3' : undefined,
      fillColor: nfz ? '#222' : '#fff',
      fillOpacity: nfz ? 0.3 : 0.0,
      interactive: false,
    }).addTo(group);
    for (const r of rings) for (const p of r) bounds.extend(p);
  }

  // regions, shaded
  plan.uavs.forEach((u, i) => {
    if (!u.region?.coordinates) return;
    const c = counts.get(u.id)!;
    // many polygons per canvas layer (a region of 35 000 staircase polygons is ~100 layers, not 35 000)
    const style = { color: uavColour(i), weight: 1, opacity: 0.6, fillColor: uavColour(i), fillOpacity: 0.22, interactive: false };
    let batch: L.LatLngTuple[][][] = [];
    let n = 0;
    for (const poly of u.region.coordinates) {
      batch.push(poly.map((r) => r.map(ll)));
      for (const r of poly) n += r.length;
      c.polygons++;
      if (n >= CHUNK) {
        L.polygon(batch, style).addTo(group);
        batch = [];
        n = 0;
      }
    }
    if (batch.length) L.polygon(batch, style).addTo(group);
  });

  // paths: coverage solid, transit dashed; the vertices of each UAV's path in order for the numbers
  const vertices = new Map<string, L.LatLngTuple[]>();
  const parts = [...paths.features]
    .filter((f) => f.properties.uav !== undefined && f.geometry.type === 'LineString')
    .sort((a, b) => (a.properties.part ?? 0) - (b.properties.part ?? 0));
  type Batch = { rings: L.LatLngTuple[][]; n: number; style: L.PolylineOptions };
  const batches = new Map<string, Batch>();
  const flush = (b: Batch) => {
    if (b.rings.length) L.polyline(b.rings, b.style).addTo(group);
    b.rings = [];
    b.n = 0;
  };
  for (const f of parts) {
    const id = f.properties.uav!;
    const i = index.get(id) ?? 0;
    const pts = (f.geometry.coordinates as Position[]).map(ll);
    const transit = f.properties.kind === 'transit';
    // one polyline per UAV, kind and ~CHUNK vertices, holding many parts as its rings: a plan of
    // 37 000 parts is a few hundred canvas layers (one stroke each), and pieces out of view are
    // culled before clipping and simplification (bench/web/pan-zoom.mjs)
    const key = `${id}\u0000${transit ? 't' : 'c'}`;
    let batch = batches.get(key);
    if (!batch) {
      batch = {
        rings: [],
        n: 0,
        style: {
          color: uavColour(i),
          weight: transit ? 2 : 2.5,
          opacity: transit ? 0.85 : 1,
          dashArray: transit ? '6 5' : undefined,
          smoothFactor: 1.5,
          interactive: false,
        },
      };
      batches.set(key, batch);
    }
    for (let s = 0; s === 0 || s < pts.length - 1; s += CHUNK) {
      const piece = pts.slice(s, s + CHUNK + 1);
      batch.rings.push(piece);
      batch.n += piece.length;
      if (batch.n >= CHUNK) flush(batch);
    }
    const c = counts.get(id);
    if (c) c.paths++;
    const list = vertices.get(id) ?? [];
    for (const p of pts) {
      const last = list[list.length - 1];
      if (!last || last[0] !== p[0] || last[1] !== p[1]) list.push(p);
      bounds.extend(p);
    }
    vertices.set(id, list);
  }
  for (const b of batches.values()) flush(b);

  // start (filled circle) and return (ring) points
  plan.uavs.forEach((u, i) => {
    const list = vertices.get(u.id);
    const start = u.start ? ll(u.start) : list?.[0];
    const end = list?.[list.length - 1];
    if (start)
      L.circleMarker(start, { radius: 7, color: '#fff', weight: 2, fillColor: uavColour(i), fillOpacity: 1 })
        .bindTooltip(`${u.id}: start`)
        .addTo(group);
    if (end)
      L.circleMarker(end, { radius: 11, color: uavColour(i), weight: 3, fill: false })
        .bindTooltip(`${u.id}: return`)
        .addTo(group);
    const c = counts.get(u.id);
    if (c) c.waypoints = list?.length ?? 0;
  });

  // waypoint numbers: only from LABEL_ZOOM, only in view
  const labels = L.layerGroup().addTo(group);
  const refresh = () => {
    labels.clearLayers();
    const zoom = map.getZoom();
    if (!withLabels || zoom === undefined || zoom < LABEL_ZOOM) return;
    const view = map.getBounds().pad(0.1);
    let n = 0;
    for (const [id, list] of vertices) {
      const colour = uavColour(index.get(id) ?? 0);
      for (let k = 0; k < list.length && n < MAX_LABELS; k++) {
        if (!view.contains(list[k])) continue;
        L.marker(list[k], {
          interactive: false,
          keyboard: false,
          icon: L.divIcon({
            className: 'plan-wp',
            html: `<span style="border-color:${colour}">${k + 1}</span>`,
            iconSize: [0, 0],
          }),
        }).addTo(labels);
        n++;
      }
    }
  };
  map.on('zoomend moveend', refresh);
  group.addTo(map);
  refresh();
  return {
    group,
    bounds: bounds.isValid() ? bounds : null,
    counts,
    remove() {
      map.off('zoomend moveend', refresh);
      group.remove();
    },
  };
}
