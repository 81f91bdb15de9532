// A plan on a Leaflet map: each UAV's region shaded and its path in its colour (the CLI's palette),
// transit legs dashed, the area and its no-fly zones, start and return points, and waypoint numbers
// from zoom 17. Everything but the start and return markers is drawn as 256-px canvas tiles of a
// GridLayer (plan-geometry.ts, in a worker through plan-source.ts): each zoom's tiles are drawn once,
// simplified for that zoom (Douglas–Peucker, 1 px), while Leaflet scales the previous zoom's tiles
// during the zoom animation and keeps them until the new ones are ready; a pan draws only the tiles
// that come into view (README: "Drawing large plans").
import L from 'leaflet';
import type { PathsGeoJson, PlanJson } from './plan-geometry.ts';
import { drawPlanTile, type PreparedPlan } from './plan-source.ts';

export type { PathsGeoJson, PlanJson };

/** The pane of the plan's tiles: above map tiles, below the overlay pane (heatmap, start and return markers). */
const PANE = 'planTiles';

export interface DrawnPlan {
  group: L.LayerGroup;
  bounds: L.LatLngBounds | null;
  remove(): void;
}

/** The GridLayer whose tiles are a prepared plan's regions and paths. */
const PlanTiles = L.GridLayer.extend({
  createTile(this: L.GridLayer & { _plan: PreparedPlan; _cancels: Map<HTMLElement, () => void> }, coords: L.Coords, done: L.DoneCallback) {
    const tile = L.DomUtil.create('canvas', 'plan-tile') as HTMLCanvasElement;
    const size = this.getTileSize();
    const dpr = window.devicePixelRatio || 1;
    tile.width = Math.round(size.x * dpr);
    tile.height = Math.round(size.y * dpr);
    const t = drawPlanTile(this._plan.key, coords.z, coords.x, coords.y, size.x, dpr, tile);
    this._cancels.set(tile, t.cancel);
    void t.done.then(() => {
      this._cancels.delete(tile);
      done(undefined, tile);
    });
    return tile;
  },
});

export function drawPlan(map: L.Map, prepared: PreparedPlan): DrawnPlan {
  const { summary } = prepared;
  const group = L.layerGroup();
  const bounds = summary.bounds ? L.latLngBounds(summary.bounds) : null;

  // the area, no-fly zones, regions, paths and waypoint numbers
  if (!map.getPane(PANE)) map.createPane(PANE).style.zIndex = '350';
  const tiles = new (PlanTiles as unknown as typeof L.GridLayer)({
    pane: PANE,
    tileSize: 256,
    noWrap: true,
    updateWhenZooming: false,
    keepBuffer: 2,
    bounds: bounds ? bounds.pad(0.05) : undefined,
    className: 'plan-tiles',
  }) as L.GridLayer & { _plan: PreparedPlan; _cancels: Map<HTMLElement, () => void> };
  tiles._plan = prepared;
  tiles._cancels = new Map();
  tiles.on('tileunload', (e: L.TileEvent) => {
    tiles._cancels.get(e.tile)?.();
    tiles._cancels.delete(e.tile);
  });
  // data-state on the tiles' container: "loading" while tiles in view are being drawn, then "ready"
  tiles.on('loading load', (e: L.LeafletEvent) => {
    const c = tiles.getContainer();
    if (c) c.dataset.state = e.type === 'load' ? 'ready' : 'loading';
  });
  tiles.addTo(group);

  // start (filled circle) and return (ring) points
  for (const u of summary.uavs) {
    if (u.start)
      L.circleMarker(u.start, { radius: 7, color: '#fff', weight: 2, fillColor: u.colour, fillOpacity: 1 })
        .bindTooltip(`${u.id}: start`)
        .addTo(group);
    if (u.end)
      L.circleMarker(u.end, { radius: 11, color: u.colour, weight: 3, fill: false })
        .bindTooltip(`${u.id}: return`)
        .addTo(group);
  }

  group.addTo(map);
  return {
    group,
    bounds,
    remove() {
      group.remove();
    },
  };
}
