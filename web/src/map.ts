// The map: Leaflet with the canvas renderer (long paths stay smooth), a neutral background that works
// without tiles, a scale bar and the pointer's coordinates. Tiles: OpenStreetMap by default, another
// URL with ?tiles=URL-template, none with ?tiles=off (field laptops offline, and the tests).
import L from 'leaflet';
import 'leaflet/dist/leaflet.css';

export function tileUrl(search: string): string | null {
  const p = new URLSearchParams(search).get('tiles');
  if (p === 'off') return null;
  return p ?? 'https://tile.openstreetmap.org/{z}/{x}/{y}.png';
}

export function createMap(el: HTMLElement): L.Map {
  const map = L.map(el, { preferCanvas: true, zoomControl: true }).setView([40.604, 22.906], 15);
  const url = tileUrl(window.location.search);
  if (url)
    L.tileLayer(url, {
      maxZoom: 20,
      attribution: '&copy; OpenStreetMap contributors',
    }).addTo(map);
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
