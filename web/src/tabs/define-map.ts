// The Define tab's map (issue 11): the area and no-fly zones drawn and edited with geoman (vertex editing,
// holes by cutting, snapping; a vertex or shape selected and deleted; Esc, Ctrl-Z, Delete), the
// corridor's centre line and the building's footprint drawn for the Pattern section, and the layer of
// the UAVs' start and rally markers (drawn by define-uavs.ts). Every edit is read back into the document.
import { el } from '../dom.ts';
import L from 'leaflet';
import '@geoman-io/leaflet-geoman-free';
import '@geoman-io/leaflet-geoman-free/dist/leaflet-geoman.css';
import {
  areaPolygons,
  corridorOf,
  geojsonPolygons,
  nfzPolygons,
  polygonsOf,
  structureOf,
  withArea,
  withNfz,
  type MissionDoc,
  type PolygonCoords,
  type Position,
} from '../mission-doc.ts';
import { AREA_FILL, AREA_STROKE, NFZ_FILL, NFZ_STROKE, zoneLegendHtml } from '../zones.ts';
import { round, section } from './define-errors.ts';

// a building's footprint on the map
const STRUCTURE_STYLE: L.PathOptions = { color: '#5b4636', weight: 2, fillColor: '#8d6e63', fillOpacity: 0.6 };

type Kind = 'area' | 'nfz';

const toLatLngs = (p: PolygonCoords): L.LatLngExpression[][] => p.map((r) => r.map(([x, y]) => [y, x] as L.LatLngTuple));

// the area and no-fly zones as the CLI's pictures draw them (src/render/plan_map.cpp draw_plan)
const AREA_STYLE: L.PathOptions = { color: AREA_STROKE, weight: 2, fillColor: AREA_FILL, fillOpacity: 0.8 };
const NFZ_STYLE: L.PathOptions = { color: NFZ_STROKE, weight: 2, dashArray: '6 4', fillColor: NFZ_FILL, fillOpacity: 0.3 };

function isEditable(t: EventTarget | null): boolean {
  const e = t as HTMLElement | null;
  return !!e && (e.tagName === 'INPUT' || e.tagName === 'TEXTAREA' || e.tagName === 'SELECT' || e.isContentEditable);
}

/** what the next shape drawn on the map becomes */
export type DrawKind = Kind | 'cut' | 'corridor' | 'footprint';

export interface MapHost {
  doc(): MissionDoc;
  commit(d: MissionDoc): void;
  undo(): void;
  /** a short note in the status line */
  flash(text: string): void;
  /** a corridor's centre line was drawn (the map is drawn again next) */
  corridorDrawn(line: Position[]): void;
  /** a building's footprint was drawn (the map is drawn again next) */
  footprintDrawn(polys: PolygonCoords[]): void;
  /** true while the next click places a UAV's start or a rally point (define-uavs.ts) */
  isPlacing(): boolean;
  /** the map was clicked there while placing */
  place(at: [number, number]): void;
  stopPlacing(): void;
  /** the start and rally markers drawn again */
  renderStarts(): void;
}

export class DefineMap {
  /** the UAVs' start and rally markers, shown with the shapes */
  readonly markers = L.layerGroup();
  private group = L.featureGroup();
  private areaLayers: L.Polygon[] = [];
  private nfzLayers: L.Polygon[] = [];
  private drawKind: DrawKind | null = null;
  private corridorLayer: L.Polyline | null = null;
  private selLayer: L.Polygon | null = null;
  private selVertex: { layer: L.Polygon; path: number[]; el?: HTMLElement } | null = null;
  private syncTimer = 0;
  private visible = false;
  private buttons = new Map<DrawKind, HTMLButtonElement>();
  private areaInfo = el('p', { class: 'define-small muted' });

  constructor(
    private map: L.Map,
    panel: HTMLElement,
    private host: MapHost,
  ) {
    const area = section(panel, 'Area and no-fly zones');
    area.dataset.anchor = 'area no_fly_zones';
    const tools = el('div', { class: 'define-tools' });
    const drawAreaBtn = this.drawButton('area', { 'data-testid': 'draw-area', title: 'Click the corners on the map; click the first one again to close it (Esc cancels)' }, 'Draw area');
    const drawNfzBtn = this.drawButton('nfz', { 'data-testid': 'draw-nfz', class: 'define-nfz-btn', title: 'A zone the UAVs must not enter' }, 'Draw no-fly zone');
    const cutBtn = this.drawButton('cut', { 'data-testid': 'draw-hole', title: 'Cut a hole out of the area' }, 'Cut hole');
    const undoBtn = el('button', { type: 'button', 'data-testid': 'define-undo', title: 'Undo (Ctrl-Z)' }, 'Undo');
    const delBtn = el('button', { type: 'button', 'data-testid': 'define-delete', title: 'Delete the selected vertex or shape (Delete)' }, 'Delete selected');
    undoBtn.addEventListener('click', () => this.host.undo());
    delBtn.addEventListener('click', () => this.deleteSelection());
    tools.append(drawAreaBtn, drawNfzBtn, cutBtn, undoBtn, delBtn);
    const zoneKey = el('div', { class: 'zone-legend', 'data-testid': 'define-zone-legend' });
    zoneKey.innerHTML = zoneLegendHtml();
    area.append(
      tools,
      this.areaInfo,
      zoneKey,
      el('p', { class: 'define-small muted' }, 'Drag a vertex to move it, the middle of an edge to add one; click a vertex or shape then Delete to remove it. Esc cancels drawing, Ctrl-Z undoes.'),
    );
    this.install();
    document.addEventListener('keydown', (e) => this.onKey(e));
  }

  /** a button that starts (or, pressed again, stops) drawing that kind of shape; shown active meanwhile */
  drawButton(kind: DrawKind, attrs: Record<string, string>, text: string): HTMLButtonElement {
    const b = el('button', { type: 'button', ...attrs }, text);
    b.addEventListener('click', () => this.startDraw(kind));
    this.buttons.set(kind, b);
    return b;
  }

  private install(): void {
    const map = this.map;
    map.pm.setGlobalOptions({ snappable: true, snapDistance: 15, allowSelfIntersection: false } as L.PM.GlobalOptions);
    map.on('pm:create', (e) => {
      const kind = this.drawKind;
      if (kind === 'corridor') {
        this.drawKind = null;
        this.updateButtons();
        const layer = e.layer as L.Polyline;
        const line = (layer.getLatLngs() as L.LatLng[]).map((ll) => [round(ll.lng, 7), round(ll.lat, 7)] as Position);
        layer.remove();
        this.host.corridorDrawn(line);
        this.render();
        return;
      }
      if (kind === 'footprint') {
        this.drawKind = null;
        this.updateButtons();
        const layer = e.layer as L.Polygon;
        const polys = polygonsOf(layer.toGeoJSON());
        layer.remove();
        this.host.footprintDrawn(polys);
        this.render();
        return;
      }
      if (kind !== 'area' && kind !== 'nfz') return; // not drawn by this tab
      this.drawKind = null;
      this.updateButtons();
      const layer = e.layer as L.Polygon;
      const polys = polygonsOf(layer.toGeoJSON());
      layer.remove();
      const doc = this.host.doc();
      if (kind === 'area') this.host.commit(withArea(doc, [...areaPolygons(doc), ...polys]));
      else this.host.commit(withNfz(doc, [...nfzPolygons(doc), ...polys]));
      this.renderInfo();
      this.render();
    });
    map.on('pm:drawend', () => {
      if (this.drawKind !== 'cut') this.drawKind = null;
      this.updateButtons();
    });
    map.on('pm:globalcutmodetoggled', (e: { enabled: boolean }) => {
      if (!e.enabled && this.drawKind === 'cut') this.drawKind = null;
      this.updateButtons();
    });
    map.on('pm:cut', (e) => {
      const original = e.originalLayer as L.Polygon;
      const result = e.layer as L.Polygon;
      for (const arr of [this.areaLayers, this.nfzLayers]) {
        const k = arr.indexOf(original);
        if (k >= 0) arr[k] = result;
      }
      this.scheduleSync();
    });
    map.on('click', (e: L.LeafletMouseEvent) => {
      if (this.host.isPlacing() && this.visible) this.host.place([round(e.latlng.lng, 7), round(e.latlng.lat, 7)]);
      else if (!this.drawKind) this.select(null);
    });
  }

  private layerStyle(kind: Kind, selected: boolean): L.PathOptions {
    const base = kind === 'area' ? AREA_STYLE : NFZ_STYLE;
    return selected ? { ...base, weight: 4 } : base;
  }

  /** the shapes drawn again from the document (and the markers), editable while the tab is shown */
  render(): void {
    const doc = this.host.doc();
    if (this.selVertex?.el) this.selVertex.el.classList.remove('define-vertex-selected');
    this.selLayer = null;
    this.selVertex = null;
    this.group.clearLayers();
    this.areaLayers = [];
    this.nfzLayers = [];
    const add = (p: PolygonCoords, kind: Kind) => {
      const layer = L.polygon(toLatLngs(p), this.layerStyle(kind, false));
      layer.addTo(this.group);
      layer.on('pm:edit', () => this.scheduleSync());
      layer.on('pm:vertexclick', (e) => this.selectVertex(layer, e.indexPath as unknown as number[], e.markerEvent));
      layer.on('click', (e: L.LeafletMouseEvent) => {
        if (this.drawKind || this.host.isPlacing()) return;
        L.DomEvent.stopPropagation(e);
        this.select(layer);
      });
      layer.bindTooltip(kind === 'area' ? 'area' : 'no-fly zone', { sticky: true, className: 'define-tip' });
      (kind === 'area' ? this.areaLayers : this.nfzLayers).push(layer);
    };
    for (const p of areaPolygons(doc)) add(p, 'area');
    for (const p of nfzPolygons(doc)) add(p, 'nfz');
    // the corridor: its centre line (the buffered ground is drawn by the plan)
    this.corridorLayer = null;
    const c = corridorOf(doc);
    if (c && c.line.length >= 2) {
      this.corridorLayer = L.polyline(
        c.line.map(([x, y]) => [y, x] as L.LatLngTuple),
        { color: AREA_STROKE, weight: 3, dashArray: '8 6', pmIgnore: true } as L.PolylineOptions,
      );
      this.corridorLayer.bindTooltip(`corridor, ${c.width_m} m wide`, { sticky: true, className: 'define-tip' });
      this.corridorLayer.addTo(this.group);
    }
    const st = structureOf(doc);
    if (st) {
      const fp = L.polygon(toLatLngs(st.footprint), { ...STRUCTURE_STYLE, pmIgnore: true } as L.PolylineOptions);
      fp.bindTooltip(`building, ${st.height_m} m high; orbits ${st.standoff_m} m out`, { sticky: true, className: 'define-tip' });
      fp.addTo(this.group);
    }
    this.host.renderStarts();
    this.setEditing(this.visible);
    this.renderInfo();
  }

  private setEditing(on: boolean): void {
    for (const l of [...this.areaLayers, ...this.nfzLayers]) {
      if (on) l.pm.enable({ snappable: true, snapDistance: 15, allowSelfIntersection: false, draggable: false } as L.PM.EditModeOptions);
      else l.pm.disable();
    }
  }

  /** read the geometry back from the edited layers into the document */
  private scheduleSync(): void {
    clearTimeout(this.syncTimer);
    this.syncTimer = window.setTimeout(() => this.syncFromLayers(), 0);
  }

  private syncFromLayers(): void {
    const read = (ls: L.Polygon[]) =>
      ls.flatMap((l) => (this.map.hasLayer(l) || this.group.hasLayer(l) ? geojsonPolygons(l.toGeoJSON()).map((x) => x.coords) : []));
    const area = read(this.areaLayers);
    const nfz = read(this.nfzLayers);
    // geoman adds cut results to the map itself: drop them, the document is redrawn
    for (const l of [...this.areaLayers, ...this.nfzLayers]) if (!this.group.hasLayer(l)) l.remove();
    this.host.commit(withNfz(withArea(this.host.doc(), area), nfz));
    this.render();
  }

  private select(layer: L.Polygon | null): void {
    if (this.selVertex?.el) this.selVertex.el.classList.remove('define-vertex-selected');
    this.selVertex = null;
    if (this.selLayer) this.selLayer.setStyle(this.layerStyle(this.nfzLayers.includes(this.selLayer) ? 'nfz' : 'area', false));
    this.selLayer = layer;
    if (layer) layer.setStyle(this.layerStyle(this.nfzLayers.includes(layer) ? 'nfz' : 'area', true));
  }

  private selectVertex(layer: L.Polygon, path: number[], markerEvent: unknown): void {
    this.select(layer);
    const target = (markerEvent as { target?: { getElement?: () => HTMLElement | undefined } } | undefined)?.target;
    const elx = target?.getElement?.();
    elx?.classList.add('define-vertex-selected');
    this.selVertex = { layer, path: Array.isArray(path) ? path : [0, Number(path)], el: elx };
  }

  private deleteSelection(): void {
    if (this.selVertex) {
      const { layer, path } = this.selVertex;
      const latlngs = layer.getLatLngs() as unknown;
      // navigate to the ring holding the vertex: path = [ring, i] or [polygon, ring, i]
      const rings: L.LatLng[][] = path.length === 3 ? (latlngs as L.LatLng[][][])[path[0]] : (latlngs as L.LatLng[][]);
      const ringIndex = path[path.length - 2];
      const ring = rings[ringIndex];
      if (ring) {
        ring.splice(path[path.length - 1], 1);
        if (ring.length < 3) {
          if (ringIndex === 0) {
            this.removeLayer(layer);
            return;
          }
          rings.splice(ringIndex, 1);
        }
        layer.setLatLngs(latlngs as L.LatLng[][]);
        this.syncFromLayers();
      }
      return;
    }
    if (this.selLayer) {
      this.removeLayer(this.selLayer);
      return;
    }
    this.host.flash('Select a vertex or a shape on the map first.');
  }

  private removeLayer(layer: L.Polygon): void {
    this.areaLayers = this.areaLayers.filter((l) => l !== layer);
    this.nfzLayers = this.nfzLayers.filter((l) => l !== layer);
    this.group.removeLayer(layer);
    this.syncFromLayers();
  }

  private startDraw(kind: DrawKind): void {
    const map = this.map;
    const wasSame = this.drawKind === kind;
    this.cancelModes();
    if (wasSame) return; // the button toggles
    this.select(null);
    if (kind === 'corridor') {
      this.drawKind = 'corridor';
      map.pm.enableDraw('Line', {
        snappable: true,
        snapDistance: 15,
        pathOptions: { color: AREA_STROKE, weight: 3 },
        templineStyle: { color: AREA_STROKE },
        hintlineStyle: { color: AREA_STROKE, dashArray: '5 5' },
      } as L.PM.DrawModeOptions);
    } else if (kind === 'footprint') {
      this.drawKind = 'footprint';
      map.pm.enableDraw('Polygon', {
        snappable: true,
        snapDistance: 15,
        allowSelfIntersection: false,
        pathOptions: STRUCTURE_STYLE,
        templineStyle: { color: STRUCTURE_STYLE.color },
        hintlineStyle: { color: STRUCTURE_STYLE.color, dashArray: '5 5' },
      } as L.PM.DrawModeOptions);
    } else if (kind === 'cut') {
      if (this.areaLayers.length === 0) {
        this.host.flash('Draw the area first.');
        return;
      }
      this.drawKind = 'cut';
      // a copy: geoman removes the cut layers from the array it is given
      map.pm.enableGlobalCutMode({ layersToCut: [...this.areaLayers], snappable: true, allowSelfIntersection: false } as L.PM.CutModeOptions);
    } else {
      this.drawKind = kind;
      map.pm.enableDraw('Polygon', {
        snappable: true,
        snapDistance: 15,
        allowSelfIntersection: false,
        pathOptions: kind === 'area' ? AREA_STYLE : NFZ_STYLE,
        templineStyle: { color: kind === 'area' ? AREA_STROKE : NFZ_STROKE },
        hintlineStyle: { color: kind === 'area' ? AREA_STROKE : NFZ_STROKE, dashArray: '5 5' },
      } as L.PM.DrawModeOptions);
    }
    this.updateButtons();
  }

  /** drawing, cutting and placing stopped */
  cancelModes(): void {
    const map = this.map;
    this.drawKind = null;
    if (map.pm.globalDrawModeEnabled()) map.pm.disableDraw();
    if (map.pm.globalCutModeEnabled()) map.pm.disableGlobalCutMode();
    this.host.stopPlacing();
    this.updateButtons();
  }

  private updateButtons(): void {
    for (const [kind, b] of this.buttons) b.classList.toggle('active', this.drawKind === kind);
    this.map.getContainer().classList.toggle('define-drawing', this.drawKind !== null);
  }

  private onKey(e: KeyboardEvent): void {
    if (!this.visible) return;
    const map = this.map;
    if (e.key === 'Escape') {
      if (this.drawKind || this.host.isPlacing() || map.pm.globalDrawModeEnabled()) {
        this.cancelModes();
        e.preventDefault();
      } else this.select(null);
      return;
    }
    if (isEditable(e.target)) return;
    if ((e.ctrlKey || e.metaKey) && !e.shiftKey && e.key.toLowerCase() === 'z') {
      e.preventDefault();
      // while drawing (an area, a zone or a cut), Ctrl-Z takes back the last vertex
      const shapes = map.pm.Draw as unknown as Record<string, { _enabled?: boolean; _layer?: L.Polyline; _removeLastVertex?: () => void }>;
      const draw = [shapes.Polygon, shapes.Cut].find((d) => d?._enabled && d._layer && d._layer.getLatLngs().length > 0);
      if (draw) draw._removeLastVertex?.();
      else this.host.undo();
      return;
    }
    if (e.key === 'Delete' || e.key === 'Backspace') {
      if (this.selVertex || this.selLayer) {
        e.preventDefault();
        this.deleteSelection();
      }
    }
  }

  /** the line that counts the area's polygons, holes and no-fly zones */
  renderInfo(): void {
    const doc = this.host.doc();
    const a = areaPolygons(doc);
    const z = nfzPolygons(doc);
    const holes = a.reduce((n, p) => n + p.length - 1, 0);
    this.areaInfo.textContent =
      a.length === 0
        ? 'No area yet: press “Draw area” and click its corners on the map.'
        : `${a.length} area polygon${a.length > 1 ? 's' : ''}${holes ? `, ${holes} hole${holes > 1 ? 's' : ''}` : ''}, ${z.length} no-fly zone${z.length === 1 ? '' : 's'}.`;
  }

  show(): void {
    this.visible = true;
    this.group.addTo(this.map);
    this.markers.addTo(this.map);
    this.setEditing(true);
  }

  hide(): void {
    this.visible = false;
    this.cancelModes();
    this.select(null);
    this.setEditing(false);
    this.group.remove();
    this.markers.remove();
  }
}
