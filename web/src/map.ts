// The map: Leaflet with the canvas renderer (long paths stay smooth), a neutral background that works
// without tiles, a scale bar and the pointer's coordinates. Tiles: OpenStreetMap by default, another
// URL with ?tiles=URL-template, none with ?tiles=off (field laptops offline, and the tests). When the
// server has tiles of its own (`uavcover serve --tiles FILE.mbtiles`, docs/offline-maps.md) they are
// the base layer, and a layer control offers the online tiles beside them.
import L from 'leaflet';
import 'leaflet/dist/leaflet.css';

export function tileUrl(search: string): string | null {
  const p = new URLSearchParams(search).get('tiles');
  if (p === 'off') return null;
  return p ?? 'https://tile.openstreetmap.org/{z}/{x}/{y}.png';
}

/** What GET /tiles/metadata.json says (docs/api.md). */
export interface ServerTiles {
  available: boolean;
  url?: string;
  name?: string;
  attribution?: string;
  minzoom?: number;
  maxzoom?: number;
  /** west, south, east, north in degrees */
  bounds?: [number, number, number, number] | null;
}

export const OFFLINE_LAYER = 'Offline tiles (server)';
const ONLINE_LAYER = 'OpenStreetMap';

let serverTiles: ServerTiles | null = null;

/** The server's tiles, once asked (null: none, or not known yet). */
export function offlineTiles(): ServerTiles | null {
  return serverTiles?.available ? serverTiles : null;
}

/** Asks the server whether it has tiles; none when it cannot say. */
export async function loadServerTiles(): Promise<ServerTiles | null> {
  try {
    const res = await fetch('/tiles/metadata.json');
    if (!res.ok) return null;
    serverTiles = (await res.json()) as ServerTiles;
  } catch {
    serverTiles = null;
  }
  return offlineTiles();
}

function onlineLayer(url: string): L.TileLayer {
  return L.tileLayer(url, { maxZoom: 20, attribution: '&copy; OpenStreetMap contributors' });
}

/** A Leaflet layer of the server's tiles: requested only inside their bounds and zoom levels (finer
 * zooms enlarge the finest tiles, coarser ones shrink the coarsest). */
export function offlineLayer(t: ServerTiles): L.TileLayer {
  const b = t.bounds;
  return L.tileLayer(t.url ?? '/tiles/{z}/{x}/{y}', {
    maxZoom: 20,
    minNativeZoom: t.minzoom,
    maxNativeZoom: t.maxzoom,
    bounds: b ? L.latLngBounds([b[1], b[0]], [b[3], b[2]]) : undefined,
    attribution: t.attribution || `${t.name ?? 'offline tiles'} (served by uavcover)`,
    className: 'offline-tiles',
  });
}

/** The base layer a new map gets: the server's tiles when it has them, else the online ones (or none). */
export function baseTileLayer(search: string = window.location.search): L.TileLayer | null {
  const t = offlineTiles();
  if (t) return offlineLayer(t);
  const url = tileUrl(search);
  return url ? onlineLayer(url) : null;
}

export function createMap(el: HTMLElement): L.Map {
  const map = L.map(el, { preferCanvas: true, zoomControl: true }).setView([40.604, 22.906], 15);
  const url = tileUrl(window.location.search);
  const online = url ? onlineLayer(url).addTo(map) : null;
  void loadServerTiles().then((t) => {
    if (!t) return;
    const offline = offlineLayer(t).addTo(map);
    if (online) {
      online.remove();
      const layers: Record<string, L.TileLayer> = { [OFFLINE_LAYER]: offline, [ONLINE_LAYER]: online };
      L.control.layers(layers, undefined, { position: 'topright' }).addTo(map);
    }
  });
  L.control.scale({ imperial: false }).addTo(map);
  const coords = new L.Control({ position: 'bottomright' });
  coords.onAdd = () => {
    const div = L.DomUtil.create('div', 'coords');
    map.on('mousemove', (e: L.LeafletMouseEvent) => {
      div.textContent = `${e.latlng.lat.toFixed(6)}, ${e.latlng.lng.toFixed(6)}`;
    });
    return div;
  };
  coords.addTo(map);
  return map;
}
