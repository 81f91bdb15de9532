// The Define tab's mission options beyond the area grid (issues 30, 31 and 32): the structure (facade) scan's
// numbers, the oblique passes, the wind, the terrain, the auto planner's objective and the shares from
// capabilities.
// Each control writes its block of the mission document through the tab's commit; render() shows the
// document's values. The map side of a structure (drawing its footprint) is in define-map.ts, its section in
// define-pattern.ts.
import { el } from '../dom.ts';
import {
  OBJECTIVES,
  OBLIQUE_DEFAULTS,
  STRUCTURE_DEFAULTS,
  TERRAIN_DEFAULTS,
  obliqueOf,
  sharesAuto,
  structureOf,
  terrainOf,
  windOf,
  withOblique,
  withSharesAuto,
  withStructure,
  withTerrain,
  withWind,
  type MissionDoc,
  type StructureScan,
  type TerrainSource,
} from '../mission-doc.ts';
import { field, num } from './define-errors.ts';

export interface ExtrasHost {
  doc(): MissionDoc;
  commit(d: MissionDoc): void;
  /** the next map click adds a rally point (issue 31) */
  placeRally?(): void;
}

function numberInput(testid: string, min: string, max: string, title: string, placeholder = ''): HTMLInputElement {
  return el('input', { type: 'number', min, max, step: 'any', 'data-testid': testid, title, placeholder });
}

/** the structure scan's numbers (height, standoff, safe height, roof pass), shown when the pattern is a structure */
export class StructureControls {
  readonly row = el('div', { class: 'define-structure', 'data-testid': 'structure-options' });
  readonly info = el('p', { class: 'define-small muted', 'data-testid': 'structure-info' });
  private height = numberInput('structure-height', '0', '1000', 'the building’s height above the ground');
  private standoff = numberInput('structure-standoff', '0', '500', 'distance from the walls to the orbits');
  private safe = numberInput('structure-safe-height', '0', '1000', 'the lowest orbit is at least this high', String(STRUCTURE_DEFAULTS.safe_height_m));
  private top = el('input', { type: 'checkbox', 'data-testid': 'structure-top', title: 'add a nadir pass over the roof' });

  constructor(private host: ExtrasHost) {
    field(this.row, 'Height', 'structure.height_m', this.height, 'm');
    field(this.row, 'Standoff', 'structure.standoff_m', this.standoff, 'm');
    field(this.row, 'Safe height', 'structure.safe_height_m', this.safe, 'm');
    field(this.row, 'Roof pass', 'structure.top', this.top);
    this.row.appendChild(this.info);
    for (const i of [this.height, this.standoff, this.safe, this.top]) i.addEventListener('change', () => this.changed());
  }

  /** the numbers as the inputs hold them (defaults where empty) */
  values(): Omit<StructureScan, 'footprint'> {
    return {
      height_m: num(this.height.value) ?? STRUCTURE_DEFAULTS.height_m,
      standoff_m: num(this.standoff.value) ?? STRUCTURE_DEFAULTS.standoff_m,
      safe_height_m: num(this.safe.value) ?? STRUCTURE_DEFAULTS.safe_height_m,
      top: this.top.checked,
    };
  }

  private changed(): void {
    const s = structureOf(this.host.doc());
    if (s) this.host.commit(withStructure(this.host.doc(), { ...s, ...this.values() }));
  }

  render(doc: MissionDoc): void {
    const s = structureOf(doc);
    const v = s ?? { ...STRUCTURE_DEFAULTS, footprint: [] };
    this.height.value = String(v.height_m);
    this.standoff.value = String(v.standoff_m);
    this.safe.value = v.safe_height_m === STRUCTURE_DEFAULTS.safe_height_m ? '' : String(v.safe_height_m);
    this.top.checked = v.top;
    this.info.textContent = s
      ? `Footprint of ${Math.max(0, s.footprint[0].length - 1)} corners, ${s.height_m} m high; orbits ${s.standoff_m} m from the walls.`
      : 'No footprint yet: press “Draw footprint” and click the building’s corners on the map.';
  }
}

/** the oblique passes (pattern.oblique): on/off, gimbal pitch, directions, nadir grid */
export class ObliqueControls {
  readonly row = el('div', { class: 'define-oblique', 'data-testid': 'oblique-options' });
  private on = el('input', { type: 'checkbox', 'data-testid': 'oblique-on', title: 'a nadir grid plus passes with the camera tilted (Smart Oblique)' });
  private pitch = numberInput('oblique-pitch', '-89', '-1', 'camera pitch of the oblique passes (-90 is straight down)', String(OBLIQUE_DEFAULTS.gimbal_pitch_deg));
  private directions = el('select', { 'data-testid': 'oblique-directions', title: 'how many oblique passes, each with its own heading' });
  private nadir = el('input', { type: 'checkbox', 'data-testid': 'oblique-nadir', title: 'fly the nadir grid too' });
  private detail = el('div', { class: 'define-oblique-detail' });

  constructor(private host: ExtrasHost) {
    for (const d of ['1', '2', '4']) this.directions.appendChild(el('option', { value: d }, d));
    field(this.row, 'Obliques', 'pattern.oblique', this.on);
    field(this.detail, 'Oblique pitch', 'pattern.oblique.gimbal_pitch_deg', this.pitch, '°');
    field(this.detail, 'Directions', 'pattern.oblique.directions', this.directions);
    field(this.detail, 'Nadir grid', 'pattern.oblique.nadir', this.nadir);
    this.row.appendChild(this.detail);
    for (const i of [this.on, this.pitch, this.directions, this.nadir]) i.addEventListener('change', () => this.changed());
  }

  private changed(): void {
    const doc = this.host.doc();
    if (!this.on.checked) {
      this.host.commit(withOblique(doc, null));
      return;
    }
    this.host.commit(
      withOblique(doc, {
        gimbal_pitch_deg: num(this.pitch.value) ?? OBLIQUE_DEFAULTS.gimbal_pitch_deg,
        directions: Number(this.directions.value),
        nadir: this.nadir.checked,
      }),
    );
  }

  render(doc: MissionDoc): void {
    const o = obliqueOf(doc);
    const v = o ?? OBLIQUE_DEFAULTS;
    this.on.checked = o !== null;
    this.detail.hidden = o === null;
    this.pitch.value = String(v.gimbal_pitch_deg);
    this.directions.value = String(v.directions);
    this.nadir.checked = v.nadir;
  }
}

/** the wind (speed and the direction it blows from) */
export class WindControls {
  readonly row = el('div', { class: 'define-wind', 'data-testid': 'wind-options' });
  private speed = numberInput('wind-speed', '0', '100', 'wind speed at flight altitude; 0 or empty: calm', '0');
  private from = numberInput('wind-from', '0', '359', 'where the wind blows from, degrees clockwise from north', '0');

  constructor(private host: ExtrasHost) {
    field(this.row, 'Wind', 'wind wind.speed_mps', this.speed, 'm/s');
    field(this.row, 'Wind from', 'wind.from_deg', this.from, '°');
    for (const i of [this.speed, this.from]) i.addEventListener('change', () => this.changed());
  }

  private changed(): void {
    const s = num(this.speed.value);
    const f = num(this.from.value) ?? 0;
    this.host.commit(withWind(this.host.doc(), s === undefined ? null : { speed_mps: s, from_deg: f }));
  }

  render(doc: MissionDoc): void {
    const w = windOf(doc);
    this.speed.value = w ? String(w.speed_mps) : '';
    this.from.value = w ? String(w.from_deg) : '';
  }
}

/** the auto planner's objective (shown with planner "auto") */
export class ObjectiveControl {
  readonly select = el('select', { 'data-testid': 'objective-select', title: 'what “auto” keeps: the least time, the best PoC, the fewest turns or the shortest paths' });
  row!: HTMLElement;

  constructor(private host: ExtrasHost, parent: HTMLElement) {
    for (const o of OBJECTIVES) this.select.appendChild(el('option', { value: o }, o === 'poc' ? 'PoC' : o));
    this.row = field(parent, 'Objective', 'objective', this.select);
    this.select.addEventListener('change', () => {
      const d = { ...this.host.doc() };
      if (this.select.value === 'time') delete d.objective;
      else d.objective = this.select.value;
      this.host.commit(d);
    });
  }

  render(doc: MissionDoc): void {
    const auto = doc.planner === 'auto';
    this.row.hidden = !auto;
    this.select.value = typeof doc.objective === 'string' ? doc.objective : 'time';
  }
}

/** "Shares from capabilities": every UAV's share "auto" (all finish together) */
export class SharesAutoControl {
  readonly input = el('input', { type: 'checkbox', 'data-testid': 'shares-auto', title: 'shares from each UAV’s area rate (speed × swath, endurance), so that all finish together' });

  constructor(private host: ExtrasHost, parent: HTMLElement) {
    field(parent, 'Shares from capabilities', 'uavs', this.input);
    this.input.addEventListener('change', () => this.host.commit(withSharesAuto(this.host.doc(), this.input.checked)));
  }

  render(doc: MissionDoc): void {
    this.input.checked = sharesAuto(doc);
  }
}

/** one stored elevation model as GET /api/v1/dems lists it */
export interface DemEntry {
  id: number;
  name: string;
  size: number;
}

/** where the server finds elevation models: its stored DEMs, its tiles, and the upload */
export interface TerrainHost extends ExtrasHost {
  listDems(): Promise<{ items: DemEntry[]; server_tiles: boolean }>;
  uploadDem(file: File): Promise<DemEntry>;
  say(message: string, error?: boolean): void;
}

/** terrain (issue 31): the ground from an uploaded DEM or the server's tiles, following it, its tolerance
 * and climb limits */
export class TerrainControls {
  readonly row = el('div', { class: 'define-terrain', 'data-testid': 'terrain-options' });
  private source = el('select', { 'data-testid': 'terrain-source', title: 'where the ground heights come from' });
  private upload = el('input', { type: 'file', accept: '.tif,.tiff,image/tiff', 'data-testid': 'terrain-upload', title: 'upload a GeoTIFF elevation model' });
  private follow = el('input', { type: 'checkbox', 'data-testid': 'terrain-follow', title: 'fly the camera’s height above the ground under every waypoint' });
  private tolerance = numberInput('terrain-tolerance', '0.1', '100', 'largest deviation of the height above ground along a leg', String(TERRAIN_DEFAULTS.tolerance_m));
  private climb = numberInput('terrain-max-climb', '0.1', '50', 'climb limit while following: steeper legs are flown slower', '');
  private detail = el('div', { class: 'define-terrain-detail' });
  private dems: DemEntry[] = [];
  private serverTiles = false;

  constructor(private host: TerrainHost) {
    field(this.row, 'Ground', 'terrain terrain.dem_id terrain.source terrain.dem', this.source);
    field(this.row, 'Upload DEM', 'terrain.dem_id', this.upload);
    field(this.detail, 'Follow terrain', 'terrain.mode', this.follow);
    field(this.detail, 'Tolerance', 'terrain.tolerance_m', this.tolerance, 'm');
    field(this.detail, 'Max climb', 'terrain.max_climb_mps terrain.max_descent_mps', this.climb, 'm/s');
    this.row.appendChild(this.detail);
    for (const i of [this.source, this.follow, this.tolerance, this.climb]) i.addEventListener('change', () => this.changed());
    this.upload.addEventListener('change', () => void this.uploaded());
    void this.refresh();
  }

  /** the server's DEMs and tiles, into the select */
  async refresh(): Promise<void> {
    try {
      const r = await this.host.listDems();
      this.dems = r.items;
      this.serverTiles = r.server_tiles;
    } catch {
      this.dems = [];
    }
    this.fill();
    this.render(this.host.doc());
  }

  private fill(): void {
    this.source.replaceChildren(el('option', { value: 'none' }, 'Flat (no elevation model)'));
    if (this.serverTiles) this.source.appendChild(el('option', { value: 'server' }, 'The server’s DEM tiles'));
    for (const d of this.dems) this.source.appendChild(el('option', { value: `dem:${d.id}` }, `${d.name} (#${d.id})`));
  }

  private async uploaded(): Promise<void> {
    const f = this.upload.files?.[0];
    if (!f) return;
    try {
      const d = await this.host.uploadDem(f);
      await this.refresh();
      this.source.value = `dem:${d.id}`;
      this.changed();
      this.host.say(`Elevation model “${d.name}” stored (#${d.id}).`);
    } catch (e) {
      this.host.say(e instanceof Error ? e.message : String(e), true);
    }
    this.upload.value = '';
  }

  private changed(): void {
    const v = this.source.value;
    const source: TerrainSource = v.startsWith('dem:') ? { kind: 'dem', dem_id: Number(v.slice(4)) } : v === 'server' ? { kind: 'server' } : { kind: 'none' };
    const climb = num(this.climb.value);
    this.host.commit(
      withTerrain(this.host.doc(), {
        source,
        follow: this.follow.checked,
        tolerance_m: num(this.tolerance.value) ?? TERRAIN_DEFAULTS.tolerance_m,
        ...(climb === undefined ? {} : { max_climb_mps: climb, max_descent_mps: climb }),
      }),
    );
  }

  render(doc: MissionDoc): void {
    const t = terrainOf(doc);
    const want = t.source.kind === 'dem' ? `dem:${t.source.dem_id}` : t.source.kind;
    if (![...this.source.options].some((o) => o.value === want)) this.source.appendChild(el('option', { value: want }, want === 'server' ? 'The server’s DEM tiles' : `DEM #${want.slice(4)}`));
    this.source.value = want;
    this.detail.hidden = t.source.kind === 'none';
    this.follow.checked = t.follow;
    this.tolerance.value = t.tolerance_m === TERRAIN_DEFAULTS.tolerance_m ? '' : String(t.tolerance_m);
    this.climb.value = t.max_climb_mps === undefined ? '' : String(t.max_climb_mps);
  }
}

/** the flight software and field options (issue 31): the vehicle profile, its item capacity, the resume
 * overlap and the planner's rally points */
export class FieldControls {
  readonly row = el('div', { class: 'define-vehicle', 'data-testid': 'field-options' });
  private autopilot = el('select', { 'data-testid': 'autopilot-select', title: 'the flight software the missions are for: its item capacity and limits (docs/vehicle-limits.md)' });
  private items = numberInput('max-mission-items', '8', '65535', 'the vehicle’s mission item capacity where the board decides (ArduPilot)', '');
  private backoff = numberInput('resume-backoff', '0', '10000', 'a resumed flight and every later sortie start this far back along the path; empty: one photo base', '');
  private rally = el('input', { type: 'checkbox', 'data-testid': 'propose-rally', title: 'propose a safe landing point per UAV in its region, clear of the no-fly zones' });
  private addRally = el('button', { type: 'button', class: 'define-place', 'data-testid': 'rally-add', title: 'click the map where a UAV may land safely; drag a point to move it, right-click it to remove it' }, 'Add');
  private clearRally = el('button', { type: 'button', class: 'define-place', 'data-testid': 'rally-clear', title: 'remove the rally points given' }, 'Clear');
  private rallyCount = el('span', { class: 'muted define-small', 'data-testid': 'rally-count' });

  constructor(private host: ExtrasHost) {
    this.autopilot.appendChild(el('option', { value: '' }, 'any (PX4 files)'));
    for (const [v, t] of [['px4', 'PX4 (500 items)'], ['ardupilot', 'ArduPilot (~700 items)'], ['dji', 'DJI WPML'], ['litchi', 'Litchi (99 waypoints)']])
      this.autopilot.appendChild(el('option', { value: v }, t));
    field(this.row, 'Autopilot', 'autopilot', this.autopilot);
    field(this.row, 'Mission items', 'max_mission_items', this.items);
    field(this.row, 'Resume overlap', 'resume_backoff_m', this.backoff, 'm');
    const given = el('span', { class: 'define-rally-given' });
    given.append(this.addRally, this.clearRally, this.rallyCount);
    field(this.row, 'Rally points', 'rally', given);
    field(this.row, 'Propose rally', 'propose_rally', this.rally);
    this.addRally.addEventListener('click', () => host.placeRally?.());
    this.clearRally.addEventListener('click', () => {
      const d = { ...this.host.doc() };
      delete d.rally;
      this.host.commit(d);
    });
    for (const i of [this.autopilot, this.items, this.backoff, this.rally]) i.addEventListener('change', () => this.changed());
  }

  private changed(): void {
    const d = { ...this.host.doc() };
    const set = (k: string, v: unknown) => {
      if (v === undefined || v === '' || v === false) delete d[k];
      else d[k] = v;
    };
    set('autopilot', this.autopilot.value);
    const n = num(this.items.value);
    set('max_mission_items', n === undefined ? undefined : Math.round(n));
    set('resume_backoff_m', num(this.backoff.value));
    if (this.rally.checked) delete d.rally;
    set('propose_rally', this.rally.checked);
    this.host.commit(d);
  }

  render(doc: MissionDoc): void {
    this.autopilot.value = typeof doc.autopilot === 'string' ? doc.autopilot : '';
    this.items.value = typeof doc.max_mission_items === 'number' ? String(doc.max_mission_items) : '';
    this.backoff.value = typeof doc.resume_backoff_m === 'number' ? String(doc.resume_backoff_m) : '';
    this.rally.checked = doc.propose_rally === true;
    const n = rallyOf(doc).length;
    this.rallyCount.textContent = n === 0 ? '' : `${n} given`;
    this.clearRally.hidden = n === 0;
    this.addRally.disabled = this.rally.checked;
  }
}

/** the mission's own rally points, [lon, lat] (issue 31); malformed entries are left out */
export function rallyOf(doc: MissionDoc): [number, number][] {
  const r = doc.rally;
  if (!Array.isArray(r)) return [];
  return r.filter((p): p is [number, number] => Array.isArray(p) && typeof p[0] === 'number' && typeof p[1] === 'number');
}
