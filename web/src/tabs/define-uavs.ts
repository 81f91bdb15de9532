// The Define tab's UAVs (issue 11): UAVs added from the catalog or by hand, their rows (id, speed, share,
// own camera, flight limits), shares that always sum to 100 %, the start markers dragged on the map or
// placed by a click, and the mission's rally points (issue 31), placed the same way.
import { el } from '../dom.ts';
import L from 'leaflet';
import { nextUavId, sharesAuto, type MissionDoc } from '../mission-doc.ts';
import { equalShares, lockedFor, roundTo100, setShare, sharesFromDoc, toFractions } from '../shares.ts';
import { uavColour } from '../palette.ts';
import { limitsFold } from '../uav-limits.ts';
import { ownCamera, uavCameraId, type CatalogCamera } from './define-camera.ts';
import { num, round, section } from './define-errors.ts';
import { rallyOf, SharesAutoControl, type ExtrasHost } from './define-extras.ts';

/** `placing` value while the next map click adds a rally point (else it is the UAV whose start is placed) */
const RALLY = -1;

export interface CatalogUav {
  id: number;
  name: string;
  speed_mps: number;
  endurance_min: number;
  camera_id?: number;
}
type Uav = Record<string, unknown>;

export interface UavsHost {
  doc(): MissionDoc;
  commit(d: MissionDoc): void;
  /** the camera catalog */
  cameras(): CatalogCamera[];
  /** the map's drawing modes (and any placing) cancelled */
  cancelModes(): void;
  /** a hint in the status line */
  say(text: string): void;
  /** the status line back to the mission's state */
  showStatus(): void;
}

export class DefineUavs {
  readonly sharesAuto: SharesAutoControl;
  private catalog: CatalogUav[] = [];
  private shareHistory: number[] = [];
  /** the UAV rows whose flight-limits fold is open (rows are drawn again after every change) */
  private openLimits = new Set<number>();
  private placing: number | null = null;
  private uavRows: HTMLElement;
  private uavSelect: HTMLSelectElement;

  constructor(
    panel: HTMLElement,
    private map: L.Map,
    /** where the start and rally markers are drawn */
    private markers: L.LayerGroup,
    private host: UavsHost,
    /** the host of define-extras' controls (its commit draws the whole form again) */
    private extras: ExtrasHost,
  ) {
    const uavs = section(panel, 'UAVs');
    uavs.dataset.anchor = 'uavs';
    const add = el('div', { class: 'define-tools' });
    this.uavSelect = el('select', { 'data-testid': 'uav-add-catalog', 'aria-label': 'Add a UAV from the catalog' });
    this.uavSelect.addEventListener('change', () => {
      const id = Number(this.uavSelect.value);
      this.uavSelect.value = '';
      if (id) this.addUav({ catalog_id: id });
    });
    const manual = el('button', { type: 'button', 'data-testid': 'uav-add-manual' }, 'Add by hand');
    manual.addEventListener('click', () => this.addUav({ speed_mps: 5 }));
    add.append(this.uavSelect, manual);
    this.uavRows = el('div', { class: 'define-uavs' });
    uavs.append(add, this.uavRows);
    this.sharesAuto = new SharesAutoControl(extras, uavs);
  }

  /** the UAV catalog, into the "Add from the catalog" select */
  setCatalog(list: CatalogUav[]): void {
    this.catalog = list;
    this.uavSelect.replaceChildren(el('option', { value: '' }, 'Add from the catalog…'));
    for (const u of this.catalog)
      this.uavSelect.appendChild(el('option', { value: String(u.id) }, `${u.name} (${u.speed_mps} m/s, ${u.endurance_min} min)`));
  }

  /** another document: the order of the share edits is forgotten */
  reset(): void {
    this.shareHistory = [];
  }

  /** true while the next map click places a UAV's start or a rally point */
  isPlacing(): boolean {
    return this.placing !== null;
  }

  /** the map was clicked there while placing */
  place(at: [number, number]): void {
    const i = this.placing;
    if (i === null) return;
    this.stopPlacing();
    if (i === RALLY) this.setRally([...rallyOf(this.host.doc()), at]);
    else this.setUav(i, { start: at });
  }

  /** the next map click adds a rally point */
  placeRally(): void {
    this.startPlacing(RALLY);
  }

  private uavs(): Uav[] {
    const doc = this.host.doc();
    return Array.isArray(doc.uavs) ? (doc.uavs as Uav[]) : [];
  }

  /** the rows drawn again from the document, and the markers */
  render(): void {
    this.uavRows.replaceChildren();
    const list = this.uavs();
    const shares = sharesFromDoc(list.map((u) => u.share as number | undefined));
    list.forEach((u, i) => this.uavRows.appendChild(this.uavRow(u, i, shares[i])));
    if (list.length === 0) this.uavRows.appendChild(el('p', { class: 'muted define-small' }, 'No UAVs: add one from the catalog or by hand.'));
    this.renderStarts();
  }

  private uavRow(u: Uav, i: number, share: number): HTMLElement {
    const id = typeof u.id === 'string' ? u.id : `uav${i + 1}`;
    const row = el('div', { class: 'define-uav', 'data-testid': 'uav-row', 'data-id': id, 'data-index': String(i), 'data-anchor': `uavs[${i}]` });
    const top = el('div', { class: 'define-uav-top' });
    const sw = el('span', { class: 'define-swatch', title: 'colour on the map and in the plan' });
    sw.style.background = uavColour(i);
    const idInput = el('input', { type: 'text', value: id, class: 'define-uav-id', 'aria-label': 'UAV id', 'data-testid': 'uav-id', maxlength: '64' });
    const idWrap = el('span', { 'data-anchor': `uavs[${i}].id`, class: 'define-inline' });
    idWrap.appendChild(idInput);
    idInput.addEventListener('change', () => this.setUav(i, { id: idInput.value.trim() }));
    top.append(sw, idWrap);
    const cat = typeof u.catalog_id === 'number' ? this.catalog.find((c) => c.id === u.catalog_id) : undefined;
    const fromCatalog = typeof u.catalog_id === 'number';
    if (fromCatalog)
      top.appendChild(el('span', { class: 'define-uav-cat', 'data-anchor': `uavs[${i}].catalog_id`, title: 'from the UAV catalog' }, cat ? cat.name : `catalog UAV #${u.catalog_id}`));
    // the mission's speed wins over the catalog's: empty = the catalog's
    const speed = el('input', {
      type: 'number',
      min: '0.1',
      max: '50',
      step: 'any',
      value: typeof u.speed_mps === 'number' ? String(u.speed_mps) : '',
      placeholder: fromCatalog ? (cat ? String(cat.speed_mps) : '') : '5',
      'aria-label': fromCatalog ? 'Speed (empty: the catalog’s)' : 'Speed',
      title: fromCatalog ? 'empty: the catalog’s speed' : undefined,
      'data-testid': fromCatalog ? 'uav-speed-override' : 'uav-speed',
      class: 'define-uav-speed',
    });
    speed.addEventListener('change', () => this.setUav(i, { speed_mps: num(speed.value) }));
    const sp = el('span', { class: 'define-inline', 'data-anchor': `uavs[${i}].speed_mps` });
    sp.append(speed, el('span', { class: 'define-unit' }, 'm/s'));
    top.appendChild(sp);
    const rm = el('button', { type: 'button', class: 'define-remove', 'data-testid': 'uav-remove', title: `Remove ${id}`, 'aria-label': `Remove ${id}` }, '×');
    rm.addEventListener('click', () => this.removeUav(i));
    top.appendChild(rm);

    const bottom = el('div', { class: 'define-uav-bottom' });
    const slider = el('input', { type: 'range', min: '1', max: '100', step: '1', value: String(share), 'aria-label': `Share of ${id}`, 'data-testid': 'uav-share-slider' });
    const number = el('input', { type: 'number', min: '1', max: '100', step: '1', value: String(share), 'aria-label': `Share of ${id} in %`, 'data-testid': 'uav-share' });
    const shareWrap = el('span', { class: 'define-share', 'data-anchor': `uavs[${i}].share` });
    shareWrap.append(slider, number, el('span', { class: 'define-unit' }, '%'));
    if (this.uavs().length < 2) {
      slider.disabled = true;
      number.disabled = true;
      shareWrap.title = 'a single UAV covers everything';
    } else if (sharesAuto(this.host.doc())) {
      slider.disabled = true;
      number.disabled = true;
      shareWrap.title = 'shares from capabilities: the planner sizes them so that all UAVs finish together';
    }
    let timer = 0;
    slider.addEventListener('input', () => this.previewShare(i, Number(slider.value)));
    slider.addEventListener('change', () => this.setShareOf(i, Number(slider.value)));
    number.addEventListener('input', () => {
      clearTimeout(timer);
      timer = window.setTimeout(() => {
        if (num(number.value) !== undefined) this.setShareOf(i, Number(number.value));
      }, 600);
    });
    number.addEventListener('change', () => {
      clearTimeout(timer);
      if (num(number.value) !== undefined) this.setShareOf(i, Number(number.value));
      else this.refreshShares();
    });
    const place = el('button', { type: 'button', 'data-testid': 'uav-place-start', class: 'define-place' }, Array.isArray(u.start) ? 'Move start' : 'Place start');
    place.title = 'Click, then click the map where this UAV takes off (or drag its marker)';
    place.addEventListener('click', () => this.startPlacing(i));
    const startWrap = el('span', { 'data-anchor': `uavs[${i}].start`, class: 'define-inline' });
    startWrap.appendChild(place);
    bottom.append(shareWrap, startWrap);
    row.append(top, bottom);
    // its own camera (heterogeneous cameras): only beside a mission camera, at its altitude and overlaps
    const mc = this.host.doc().camera;
    if (mc && typeof mc === 'object' && this.host.cameras().length) {
      const camRow = el('span', { class: 'define-inline define-uav-camera', 'data-anchor': `uavs[${i}].camera` });
      const sel = el('select', { 'data-testid': 'uav-camera', 'aria-label': `Camera of ${id}` });
      sel.append(el('option', { value: '' }, 'the mission’s camera'));
      for (const c of this.host.cameras()) sel.append(el('option', { value: String(c.id) }, c.name));
      const mine = uavCameraId(this.host.cameras(), u);
      sel.value = mine === null ? '' : String(mine);
      if (u.camera && mine === null) {
        sel.append(el('option', { value: 'file' }, 'its own (from the file)'));
        sel.value = 'file';
      }
      sel.addEventListener('change', () => {
        if (sel.value === 'file') return;
        const own = sel.value ? ownCamera(this.host.cameras(), this.host.doc(), Number(sel.value)) : null;
        this.setUav(i, { camera: own ?? undefined });
      });
      camRow.append(el('span', { class: 'define-unit' }, 'camera'), sel);
      row.append(camRow);
    }
    row.append(
      limitsFold(u, i, (patch) => this.setUav(i, patch), {
        catalogEndurance: cat?.endurance_min,
        open: this.openLimits.has(i),
        onToggle: (open) => (open ? this.openLimits.add(i) : this.openLimits.delete(i)),
      }),
    );
    return row;
  }

  private setUav(i: number, patch: Uav): void {
    const list = this.uavs().map((u, k) => {
      if (k !== i) return u;
      const n = { ...u, ...patch };
      for (const [key, v] of Object.entries(patch)) if (v === undefined || v === '') delete n[key];
      return n;
    });
    this.host.commit({ ...this.host.doc(), uavs: list });
    this.render();
  }

  private withShares(list: Uav[], percent: number[]): Uav[] {
    const f = toFractions(percent);
    return list.map((u, k) => ({ ...u, share: f[k] }));
  }

  private addUav(u: Uav): void {
    const list = this.uavs();
    const id = nextUavId(list.map((x) => String(x.id ?? '')));
    const next = [...list, { id, ...u }];
    this.shareHistory = [];
    this.host.commit({ ...this.host.doc(), uavs: next.length > 1 ? this.withShares(next, equalShares(next.length)) : next });
    this.render();
  }

  private removeUav(i: number): void {
    const list = this.uavs();
    const shares = sharesFromDoc(list.map((u) => u.share as number | undefined));
    const rest = list.filter((_, k) => k !== i);
    const restShares = roundTo100(shares.filter((_, k) => k !== i));
    this.shareHistory = [];
    const uavs = rest.length > 1 ? this.withShares(rest, restShares) : rest.map((u) => ({ ...u, share: 1 }));
    this.host.commit({ ...this.host.doc(), uavs });
    this.render();
  }

  private currentShares(): number[] {
    return sharesFromDoc(this.uavs().map((u) => u.share as number | undefined));
  }

  private nextShares(i: number, v: number): number[] {
    const cur = this.currentShares();
    return setShare(cur, i, v, lockedFor(this.shareHistory, i, cur.length));
  }

  private previewShare(i: number, v: number): void {
    this.refreshShares(this.nextShares(i, v));
  }

  private setShareOf(i: number, v: number): void {
    const next = this.nextShares(i, v);
    this.shareHistory = [i, ...this.shareHistory.filter((k) => k !== i)];
    this.host.commit({ ...this.host.doc(), uavs: this.withShares(this.uavs(), next) });
    this.refreshShares(next);
    // a share the operator asked for but cannot have (0 %, or all of it): say why, on that row
    this.uavRows.querySelectorAll('[data-testid="share-note"]').forEach((x) => x.remove());
    if (Math.round(v) !== next[i]) {
      const row = this.uavRows.querySelectorAll<HTMLElement>('[data-testid="uav-row"]')[i];
      const id = String(this.uavs()[i]?.id ?? `uav${i + 1}`);
      const why = Math.round(v) < next[i] ? `a share is at least 1 % — remove ${id} (×) to leave it out` : `each other UAV keeps at least 1 %`;
      row?.append(el('div', { class: 'define-share-note', 'data-testid': 'share-note', role: 'status' }, `${id}: ${next[i]} %, ${why}.`));
    }
  }

  /** show shares in the rows without rebuilding them (keeps the focus) */
  private refreshShares(shares = this.currentShares()): void {
    this.uavRows.querySelectorAll<HTMLElement>('[data-testid="uav-row"]').forEach((row, k) => {
      const s = String(shares[k] ?? 0);
      const slider = row.querySelector<HTMLInputElement>('[data-testid="uav-share-slider"]');
      const number = row.querySelector<HTMLInputElement>('[data-testid="uav-share"]');
      if (slider && slider.value !== s) slider.value = s;
      if (number && number.value !== s && document.activeElement !== number) number.value = s;
      else if (number && document.activeElement === number && Number(number.value) !== shares[k]) number.value = s;
    });
  }

  /** the start and rally markers drawn again from the document */
  renderStarts(): void {
    this.markers.clearLayers();
    this.uavs().forEach((u, i) => {
      const s = u.start;
      if (!Array.isArray(s) || typeof s[0] !== 'number' || typeof s[1] !== 'number') return;
      const id = typeof u.id === 'string' ? u.id : `uav${i + 1}`;
      const icon = L.divIcon({
        className: 'define-start-icon',
        html: `<div class="define-start" data-testid="uav-start" data-id="${id.replace(/[^A-Za-z0-9_.-]/g, '')}" style="background:${uavColour(i)}">${i + 1}</div>`,
        iconSize: [24, 24],
        iconAnchor: [12, 12],
      });
      const m = L.marker([s[1], s[0]], { icon, draggable: true, pmIgnore: true, title: `${id} start`, keyboard: false, autoPan: true });
      m.on('dragend', () => {
        const ll = m.getLatLng();
        this.setUav(i, { start: [round(ll.lng, 7), round(ll.lat, 7)] });
      });
      m.addTo(this.markers);
    });
    // the rally points given (issue 31): drag to move, right-click to remove
    const rally = rallyOf(this.host.doc());
    rally.forEach(([lon, lat], k) => {
      const icon = L.divIcon({ className: 'define-start-icon', html: `<div class="define-rally" data-testid="rally-point">R${k + 1}</div>`, iconSize: [26, 26], iconAnchor: [13, 13] });
      const m = L.marker([lat, lon], { icon, draggable: true, pmIgnore: true, title: `rally point ${k + 1}: drag to move, right-click to remove`, keyboard: false, autoPan: true });
      m.on('dragend', () => {
        const ll = m.getLatLng();
        const next = [...rally];
        next[k] = [round(ll.lng, 7), round(ll.lat, 7)];
        this.setRally(next);
      });
      m.on('contextmenu', (e: L.LeafletMouseEvent) => {
        L.DomEvent.preventDefault(e.originalEvent);
        this.setRally(rally.filter((_, j) => j !== k));
      });
      m.addTo(this.markers);
    });
  }

  /** the mission's rally points: given ones replace the planner's proposal */
  private setRally(points: [number, number][]): void {
    const d = { ...this.host.doc() };
    if (points.length === 0) delete d.rally;
    else {
      d.rally = points;
      delete d.propose_rally;
    }
    this.extras.commit(d);
    this.renderStarts();
  }

  private startPlacing(i: number): void {
    this.host.cancelModes();
    this.placing = i;
    this.map.getContainer().classList.add('define-placing');
    this.uavRows.querySelectorAll('[data-testid="uav-place-start"]').forEach((b, k) => b.classList.toggle('active', k === i));
    this.host.say(
      i === RALLY ? 'Click the map where a UAV may land safely (Esc cancels).' : `Click the map where ${String(this.uavs()[i]?.id ?? `UAV ${i + 1}`)} takes off (Esc cancels).`,
    );
  }

  stopPlacing(): void {
    if (this.placing === null) return;
    this.placing = null;
    this.map.getContainer().classList.remove('define-placing');
    this.uavRows.querySelectorAll('[data-testid="uav-place-start"]').forEach((b) => b.classList.remove('active'));
    this.host.showStatus();
  }
}
