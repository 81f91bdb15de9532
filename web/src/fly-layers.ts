// The Fly tab on the Leaflet map: the plan's paths faintly in each UAV's colour (transit dashed), its
// coverage waypoints coloured by status (Hong et al. Fig. 14: pending grey, current yellow, reached
// green, skipped red), reassigned paths dashed, each UAV as an arrow rotated by its heading in its
// palette colour with its trail, and the flown coverage overlay (GET /flights/{id}/coverage.png).
//
// Everything is updated in place: a flight update moves markers (setLatLng and a CSS rotation),
// replaces a trail only when it changed, and restyles only the waypoints whose status changed. The
// waypoints and the lines have canvas renderers of their own (panes flyWaypoints and flyLines), so a
// moving trail never redraws thousands of waypoints.
import L from 'leaflet';
import { AREA_STROKE, NFZ_FILL, NFZ_FILL_OPACITY, NFZ_STROKE } from './zones.ts';
import { changedIndices, STATUS_COLOUR, STATUS_NAME, type FlightMission, type Status, type UavLines } from './fly-model.ts';

const PANES: [string, number][] = [
  ['flyZones', 355],
  ['flyCoverage', 360],
  ['flyLines', 380],
  ['flyWaypoints', 390],
];

/** What the layers show of one UAV at one moment (live, or a replay frame). */
export interface UavFrame {
  uav: string;
  lat: number | null;
  lon: number | null;
  heading: number;
  /** waypoint statuses of the UAV's own plan, one character each */
  statuses: string;
  /** [lat, lon] points of the trail, or null to leave it as it is */
  trail: [number, number][] | null;
  lost: boolean;
  phase: string;
  missions?: FlightMission[];
}

interface UavLayer {
  colour: string;
  waypoints: [number, number][];
  dots: L.CircleMarker[];
  statuses: string;
  marker: L.Marker | null;
  arrow: HTMLElement | null;
  trail: L.Polyline;
  trailKey: string;
  planned: L.Polyline[];
  reassigned: Map<string, { line: L.Polyline; dots: L.CircleMarker[]; statuses: string }>;
}

const dotStyle = (s: Status, base: number): L.CircleMarkerOptions => ({
  radius: s === 'C' ? base + 2.5 : base,
  color: s === 'C' ? '#7a6500' : '#ffffff',
  weight: s === 'C' ? 2 : 1,
  fillColor: STATUS_COLOUR[s],
  fillOpacity: 1,
  opacity: 1,
});

const arrowSvg = (colour: string) =>
  `<svg viewBox="-14 -14 28 28" width="28" height="28" aria-hidden="true"><path d="M0,-12 L9,10 L0,5 L-9,10 Z" fill="${colour}" stroke="#fff" stroke-width="2" stroke-linejoin="round"/></svg>`;

export class FlyLayers {
  private group = L.layerGroup();
  private zones = L.layerGroup();
  private zonesRenderer: L.Canvas;
  zoneCount = { area: 0, nfz: 0 };
  private lines: L.Canvas;
  private dotsRenderer: L.Canvas;
  private uavs = new Map<string, UavLayer>();
  private coverage: L.ImageOverlay | null = null;
  private coverageLoading = false;
  private shown = false;
  /** the radius of a waypoint dot: smaller when a UAV has many */
  private dotRadius = 4;

  constructor(private map: L.Map) {
    for (const [name, z] of PANES) if (!map.getPane(name)) map.createPane(name).style.zIndex = String(z);
    map.getPane('flyCoverage')!.style.pointerEvents = 'none';
    this.lines = L.canvas({ pane: 'flyLines', padding: 0.2 });
    this.dotsRenderer = L.canvas({ pane: 'flyWaypoints', padding: 0.2 });
    this.zonesRenderer = L.canvas({ pane: 'flyZones', padding: 0.2 });
    map.getPane('flyZones')!.style.pointerEvents = 'none';
  }

  /** The mission's area (outlined) and no-fly zones (red, dashed outline), as in the Define and Plan tabs. */
  setZones(zones: { area: [number, number][][][]; nfz: [number, number][][][] }): void {
    this.zones.clearLayers();
    for (const p of zones.area)
      L.polygon(p, { renderer: this.zonesRenderer, color: AREA_STROKE, weight: 2, fill: false, interactive: false, className: 'fly-area' }).addTo(this.zones);
    for (const p of zones.nfz)
      L.polygon(p, { renderer: this.zonesRenderer, color: NFZ_STROKE, weight: 2, dashArray: '6 4', fillColor: NFZ_FILL, fillOpacity: NFZ_FILL_OPACITY, interactive: false }).addTo(this.zones);
    this.zoneCount = { area: zones.area.length, nfz: zones.nfz.length };
    const pane = this.map.getPane('flyZones')!;
    pane.dataset.area = String(zones.area.length);
    pane.dataset.nfz = String(zones.nfz.length);
  }

  /** The plan's UAVs in order (the palette index) and their lines; clears everything else. */
  setPlan(uavs: { id: string; colour: string }[], lines: Map<string, UavLines>): void {
    this.group.clearLayers();
    this.uavs.clear();
    this.removeCoverage();
    const total = [...lines.values()].reduce((n, u) => n + u.waypoints.length, 0);
    this.dotRadius = total > 4000 ? 2.5 : total > 1500 ? 3 : 4;
    for (const u of uavs) {
      const l = lines.get(u.id) ?? { waypoints: [], coverage: [], transit: [] };
      const planned: L.Polyline[] = [];
      for (const c of l.coverage)
        planned.push(L.polyline(c, { renderer: this.lines, color: u.colour, weight: 2, opacity: 0.45, interactive: false }).addTo(this.group));
      for (const c of l.transit)
        planned.push(L.polyline(c, { renderer: this.lines, color: u.colour, weight: 1.5, opacity: 0.4, dashArray: '6 5', interactive: false }).addTo(this.group));
      const trail = L.polyline([], { renderer: this.lines, color: u.colour, weight: 3, opacity: 0.9, interactive: false }).addTo(this.group);
      const status = (i: number) => STATUS_NAME[(this.uavs.get(u.id)?.statuses[i] ?? 'P') as Status] ?? '';
      const dots = l.waypoints.map((p, i) =>
        L.circleMarker(p, { renderer: this.dotsRenderer, ...dotStyle('P', this.dotRadius), interactive: true })
          .bindTooltip(() => `${u.id} waypoint ${i}: ${status(i)}`, { direction: 'top' })
          .addTo(this.group),
      );
      this.uavs.set(u.id, {
        colour: u.colour,
        waypoints: l.waypoints,
        dots,
        statuses: 'P'.repeat(dots.length),
        marker: null,
        arrow: null,
        trail,
        trailKey: '',
        planned,
        reassigned: new Map(),
      });
    }
  }

  show(): void {
    if (this.shown) return;
    this.shown = true;
    this.zones.addTo(this.map);
    this.group.addTo(this.map);
    this.coverage?.addTo(this.map);
  }

  hide(): void {
    if (!this.shown) return;
    this.shown = false;
    this.zones.remove();
    this.group.remove();
    this.coverage?.remove();
  }

  /** All UAVs back to their plan: every waypoint pending, no markers, trails or reassigned paths. */
  reset(): void {
    for (const [id, u] of this.uavs) {
      this.update({ uav: id, lat: null, lon: null, heading: 0, statuses: 'P'.repeat(u.dots.length), trail: [], lost: false, phase: 'idle', missions: [] });
      u.marker?.remove();
      u.marker = null;
      u.arrow = null;
    }
    this.removeCoverage();
  }

  /** Applies one UAV's frame in place. */
  update(f: UavFrame): void {
    const u = this.uavs.get(f.uav);
    if (!u) return;
    // waypoints: restyle the changed ones only
    if (f.statuses !== u.statuses) {
      const next = f.statuses.length === u.dots.length ? f.statuses : f.statuses.slice(0, u.dots.length).padEnd(u.dots.length, 'P');
      for (const i of changedIndices(u.statuses, next)) {
        const s = next[i] as Status;
        const d = u.dots[i];
        d.setStyle(dotStyle(s, this.dotRadius));
        d.setRadius(s === 'C' ? this.dotRadius + 2.5 : this.dotRadius);
        if (s === 'C') d.bringToFront();
      }
      u.statuses = next;
    }
    // the trail
    if (f.trail) {
      const n = f.trail.length;
      const key = n ? `${n}:${f.trail[n - 1][0]}:${f.trail[n - 1][1]}:${f.trail[0][0]}:${f.trail[0][1]}` : '';
      if (key !== u.trailKey) {
        u.trailKey = key;
        u.trail.setLatLngs(f.trail);
      }
    }
    // the UAV
    if (f.lat !== null && f.lon !== null) {
      if (!u.marker) {
        const icon = L.divIcon({ className: 'fly-uav', html: `<div class="fly-uav-arrow">${arrowSvg(u.colour)}</div><span class="fly-uav-label">${escapeHtml(f.uav)}</span>`, iconSize: [28, 28], iconAnchor: [14, 14] });
        u.marker = L.marker([f.lat, f.lon], { icon, keyboard: false, zIndexOffset: 1000 }).addTo(this.group);
        const e = u.marker.getElement();
        if (e) {
          e.dataset.testid = 'fly-uav-marker';
          e.dataset.uav = f.uav;
          u.arrow = e.querySelector('.fly-uav-arrow');
        }
      } else u.marker.setLatLng([f.lat, f.lon]);
      const e = u.marker.getElement();
      if (e) {
        e.dataset.lat = f.lat.toFixed(7);
        e.dataset.lon = f.lon.toFixed(7);
        e.dataset.phase = f.phase;
        e.classList.toggle('fly-uav-lost', f.lost);
        e.classList.toggle('fly-uav-down', f.phase === 'failed' || f.phase === 'landed' || f.phase === 'done');
      }
      if (u.arrow) u.arrow.style.transform = `rotate(${Math.round(f.heading)}deg)`;
    }
    // reassigned missions: dashed, their waypoints coloured by their own statuses
    if (f.missions) this.updateReassigned(u, f.missions);
  }

  private updateReassigned(u: UavLayer, missions: FlightMission[]): void {
    const seen = new Set<string>();
    missions.forEach((m, k) => {
      if (m.kind !== 'reassigned' || !Array.isArray(m.path) || m.path.length < 2) return;
      const key = `${m.reassignment ?? 'r'}:${m.index ?? k}`;
      seen.add(key);
      let r = u.reassigned.get(key);
      const pts = m.path.filter((p) => Array.isArray(p) && p.length >= 2).map((p) => [p[1], p[0]] as [number, number]);
      if (!r) {
        const line = L.polyline(pts, { renderer: this.lines, color: u.colour, weight: 3, opacity: 0.95, dashArray: '10 7', interactive: false }).addTo(this.group);
        const statuses = m.waypoints ?? '';
        // the path's vertices are the mission's coverage waypoints when the counts agree
        const dots = statuses.length === pts.length ? pts.map((p) => L.circleMarker(p, { renderer: this.dotsRenderer, ...dotStyle('P', this.dotRadius), interactive: false }).addTo(this.group)) : [];
        r = { line, dots, statuses: 'P'.repeat(dots.length) };
        u.reassigned.set(key, r);
      }
      const next = m.waypoints ?? '';
      if (r.dots.length && next.length === r.dots.length && next !== r.statuses) {
        for (const i of changedIndices(r.statuses, next)) r.dots[i].setStyle(dotStyle(next[i] as Status, this.dotRadius)).setRadius(next[i] === 'C' ? this.dotRadius + 2.5 : this.dotRadius);
        r.statuses = next;
      }
    });
    for (const [key, r] of u.reassigned)
      if (!seen.has(key)) {
        r.line.remove();
        for (const d of r.dots) d.remove();
        u.reassigned.delete(key);
      }
    // how many reassigned paths are drawn, on the lines' pane (for tests and tools)
    const pane = this.map.getPane('flyLines');
    if (pane) pane.dataset.reassigned = String([...this.uavs.values()].reduce((n, x) => n + x.reassigned.size, 0));
  }

  /**
   * Shows (or refreshes) the flown coverage overlay: the new image is loaded first and swapped in once
   * it arrived, so the overlay never blinks.
   */
  setCoverage(url: string, bounds: [[number, number], [number, number]]): void {
    if (this.coverageLoading) return;
    this.coverageLoading = true;
    const img = new Image();
    const done = () => {
      this.coverageLoading = false;
    };
    img.onload = () => {
      done();
      if (!this.uavs.size) return;
      if (!this.coverage) {
        this.coverage = L.imageOverlay(url, bounds, { pane: 'flyCoverage', opacity: 0.55, interactive: false, className: 'fly-coverage' });
        if (this.shown) this.coverage.addTo(this.map);
      } else {
        this.coverage.setUrl(url);
        this.coverage.setBounds(L.latLngBounds(bounds));
      }
    };
    img.onerror = done;
    img.src = url;
  }

  removeCoverage(): void {
    this.coverage?.remove();
    this.coverage = null;
  }

  /** Pans the map to a UAV (when it has a position). */
  focus(uav: string): void {
    const m = this.uavs.get(uav)?.marker;
    if (m && this.shown) this.map.panTo(m.getLatLng());
  }

  /** The plan's bounds (its waypoints and lines), for fitting the view. */
  bounds(): L.LatLngBounds | null {
    let b: L.LatLngBounds | null = null;
    for (const u of this.uavs.values())
      for (const l of u.planned) {
        const lb = l.getBounds();
        if (lb.isValid()) b = b ? b.extend(lb) : L.latLngBounds(lb.getSouthWest(), lb.getNorthEast());
      }
    return b;
  }
}

function escapeHtml(s: string): string {
  return s.replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}
