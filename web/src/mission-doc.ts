// The uavcover v1 mission document (docs/mission-format.md) as the web app edits it: geometry in and
// out of the document, drafts, and matching the server's field paths to the inputs. Pure (unit-tested).

export type Position = [number, number];
export type Ring = Position[];
/** a polygon: exterior ring then holes */
export type PolygonCoords = Ring[];
export type MissionDoc = Record<string, unknown>;

interface GeoLike {
  type?: unknown;
  coordinates?: unknown;
  geometry?: unknown;
  geometries?: unknown;
  features?: unknown;
  properties?: unknown;
}

function isPosition(p: unknown): p is Position {
  return Array.isArray(p) && p.length >= 2 && typeof p[0] === 'number' && typeof p[1] === 'number';
}

function cleanRing(r: unknown): Ring | null {
  if (!Array.isArray(r)) return null;
  const ring = r.filter(isPosition).map((p) => [p[0], p[1]] as Position);
  return ring.length >= 3 ? ring : null;
}

function cleanPolygon(c: unknown): PolygonCoords | null {
  if (!Array.isArray(c)) return null;
  const rings = c.map(cleanRing);
  if (!rings[0]) return null;
  return rings.filter((r): r is Ring => r !== null);
}

/** the polygons of a GeoJSON Polygon/MultiPolygon (or a Feature wrapping one); others give [] */
export function polygonsOf(g: unknown): PolygonCoords[] {
  if (!g || typeof g !== 'object') return [];
  const o = g as GeoLike;
  if (o.type === 'Feature') return polygonsOf(o.geometry);
  if (o.type === 'Polygon') {
    const p = cleanPolygon(o.coordinates);
    return p ? [p] : [];
  }
  if (o.type === 'MultiPolygon' && Array.isArray(o.coordinates))
    return o.coordinates.map(cleanPolygon).filter((p): p is PolygonCoords => p !== null);
  return [];
}

/** the area's polygons */
export function areaPolygons(doc: MissionDoc | null): PolygonCoords[] {
  return doc ? polygonsOf(doc.area) : [];
}

/** the no-fly zones, one polygon each */
export function nfzPolygons(doc: MissionDoc | null): PolygonCoords[] {
  const z = doc?.no_fly_zones;
  return Array.isArray(z) ? z.flatMap(polygonsOf) : [];
}

/** a GeoJSON geometry for polygons: none → undefined, one → Polygon, several → MultiPolygon */
export function geometryOf(polys: PolygonCoords[]): Record<string, unknown> | undefined {
  if (polys.length === 0) return undefined;
  if (polys.length === 1) return { type: 'Polygon', coordinates: polys[0] };
  return { type: 'MultiPolygon', coordinates: polys };
}

/** a copy of the document with these area polygons (the area removed when there are none) */
export function withArea(doc: MissionDoc, polys: PolygonCoords[]): MissionDoc {
  const out = { ...doc };
  const g = geometryOf(polys);
  if (g) out.area = g;
  else delete out.area;
  return out;
}

/** a copy of the document with these no-fly zones */
export function withNfz(doc: MissionDoc, polys: PolygonCoords[]): MissionDoc {
  return { ...doc, no_fly_zones: polys.map((p) => ({ type: 'Polygon', coordinates: p })) };
}

/** [minlon, minlat, maxlon, maxlat] of the area and no-fly zones, or null */
export function docBbox(doc: MissionDoc | null): [number, number, number, number] | null {
  const pts = [...areaPolygons(doc), ...nfzPolygons(doc), ...(structureOf(doc) ? [structureOf(doc)!.footprint] : [])]
    .flat(2)
    .concat(corridorOf(doc)?.line ?? []);
  if (pts.length === 0) return null;
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (const [x, y] of pts) {
    x0 = Math.min(x0, x);
    y0 = Math.min(y0, y);
    x1 = Math.max(x1, x);
    y1 = Math.max(y1, y);
  }
  return [x0, y0, x1, y1];
}

/** |area| of a ring in square degrees scaled by cos(latitude) (enough to compare sizes) */
export function ringArea(ring: Ring): number {
  if (ring.length < 3) return 0;
  const lat0 = (ring.reduce((a, p) => a + p[1], 0) / ring.length) * (Math.PI / 180);
  let s = 0;
  for (let i = 0; i < ring.length; i++) {
    const [x1, y1] = ring[i];
    const [x2, y2] = ring[(i + 1) % ring.length];
    s += x1 * y2 - x2 * y1;
  }
  return Math.abs(s / 2) * Math.cos(lat0);
}

/** point in ring by ray casting */
export function pointInRing(p: Position, ring: Ring): boolean {
  let inside = false;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
    const [xi, yi] = ring[i];
    const [xj, yj] = ring[j];
    if (yi > p[1] !== yj > p[1] && p[0] < ((xj - xi) * (p[1] - yi)) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

/** every vertex of `inner`'s exterior lies inside `outer`'s exterior */
export function polygonInside(inner: PolygonCoords, outer: PolygonCoords): boolean {
  return inner[0].every((p) => pointInRing(p, outer[0]));
}

export type Role = 'area' | 'nfz' | undefined;

/**
 * Sort imported polygons into area and no-fly zones: those marked as no-fly zones are zones; of the
 * rest, the largest is the area, polygons inside an area polygon are zones, and the others (outside
 * it) are further area polygons.
 */
export function classify(items: { coords: PolygonCoords; role?: Role }[]): {
  area: PolygonCoords[];
  nfz: PolygonCoords[];
} {
  const nfz = items.filter((i) => i.role === 'nfz').map((i) => i.coords);
  const rest = items.filter((i) => i.role !== 'nfz');
  const marked = rest.filter((i) => i.role === 'area').map((i) => i.coords);
  const open = rest
    .filter((i) => i.role !== 'area')
    .map((i) => i.coords)
    .sort((a, b) => ringArea(b[0]) - ringArea(a[0]));
  const area: PolygonCoords[] = [...marked];
  for (const p of open) {
    if (area.length === 0) area.push(p);
    else if (area.some((a) => polygonInside(p, a))) nfz.push(p);
    else area.push(p);
  }
  return { area, nfz };
}

const NFZ_ROLES = new Set(['no_fly_zone', 'nfz', 'no-fly-zone', 'no fly zone', 'obstacle']);

/** a role from a feature's properties ({"role": "no_fly_zone"} / "nfz" / "area") */
export function roleOf(props: unknown): Role {
  if (!props || typeof props !== 'object') return undefined;
  const r = (props as Record<string, unknown>).role;
  if (typeof r !== 'string') return undefined;
  const s = r.trim().toLowerCase();
  if (NFZ_ROLES.has(s)) return 'nfz';
  if (s === 'area') return 'area';
  return undefined;
}

/** the polygons of any GeoJSON object (FeatureCollection, Feature, GeometryCollection, geometry), with roles */
export function geojsonPolygons(g: unknown, role?: Role): { coords: PolygonCoords; role?: Role }[] {
  if (!g || typeof g !== 'object') return [];
  const o = g as GeoLike;
  if (o.type === 'FeatureCollection' && Array.isArray(o.features))
    return o.features.flatMap((f) => geojsonPolygons(f, role));
  if (o.type === 'Feature') return geojsonPolygons(o.geometry, roleOf(o.properties) ?? role);
  if (o.type === 'GeometryCollection' && Array.isArray(o.geometries))
    return o.geometries.flatMap((x) => geojsonPolygons(x, role));
  return polygonsOf(o).map((coords) => ({ coords, role }));
}

/** a new mission's defaults: altitude 40 m, spacing 20 m, `uavs` UAVs (uav1, …) */
export function newDraft(name = 'New mission', uavs = 1): MissionDoc {
  return {
    name,
    altitude_m: 40,
    spacing_m: 20,
    uavs: Array.from({ length: uavs }, (_, i) => ({ id: `uav${i + 1}` })),
    mode: 'strict',
    planner: 'darp',
    seed: 1,
  };
}

/** a draft mission from imported polygons */
export function draftFromPolygons(name: string, items: { coords: PolygonCoords; role?: Role }[]): MissionDoc {
  const { area, nfz } = classify(items);
  if (area.length === 0) throw new Error('the file has no polygon to use as the area');
  return withNfz(withArea(newDraft(name), area), nfz);
}

/** a file name for the mission's JSON export */
export function fileName(name: unknown, ext = 'json'): string {
  const base = (typeof name === 'string' ? name : '')
    .replace(/[^A-Za-z0-9._ -]+/g, '_')
    .trim()
    .replace(/^\.+/, '')
    .slice(0, 100);
  return `${base || 'mission'}.${ext}`;
}

/**
 * The input that shows a server error: the anchor equal to the field path, or else the longest anchor
 * that is a prefix of it at a '.' or '[' boundary ("area.coordinates[0]" → "area"); null when none.
 */
export function matchField(path: string, anchors: Iterable<string>): string | null {
  if (!path) return null;
  let best: string | null = null;
  for (const a of anchors) {
    if (!a) continue;
    if (a === path) return a;
    if (path.startsWith(a) && (path[a.length] === '.' || path[a.length] === '[') && (!best || a.length > best.length))
      best = a;
  }
  return best;
}

/** a UAV id not yet used: uav1, uav2, … */
export function nextUavId(ids: string[], prefix = 'uav'): string {
  const used = new Set(ids.map((s) => s.toLowerCase()));
  for (let i = 1; ; i++) if (!used.has(`${prefix}${i}`.toLowerCase())) return `${prefix}${i}`;
}

/**
 * The document the Define tab edits for a stored mission: the source as submitted when it is a uavcover
 * v1 document (it keeps catalog references, `catalog_id` of UAVs and camera, which the normalised
 * mission has resolved into numbers: issue 29, defect 4), else the normalised mission (an mCPP input).
 */
export function editableDoc(m: { mission: MissionDoc; source?: unknown }): MissionDoc {
  const s = m.source;
  if (s && typeof s === 'object' && !Array.isArray(s) && 'area' in s && !('droneNo' in s)) return s as MissionDoc;
  return m.mission;
}

const FIELD_NAMES: Record<string, string> = {
  name: 'Name',
  area: 'Area',
  no_fly_zones: 'No-fly zones',
  uavs: 'UAVs',
  spacing_m: 'Spacing',
  altitude_m: 'Altitude',
  camera: 'Camera',
  'camera.altitude_m': 'Altitude',
  'camera.overlap': 'Side overlap',
  'camera.side_overlap': 'Side overlap',
  'camera.front_overlap': 'Front overlap',
  'camera.hfov_deg': 'HFOV',
  'camera.catalog_id': 'Camera',
  'camera.gimbal_pitch_deg': 'Gimbal pitch',
  mode: 'Mode',
  planner: 'Planner',
  planner_params: 'Planner parameters',
  seed: 'Seed',
  battery_reserve: 'Battery reserve',
};
const UAV_FIELDS: Record<string, string> = {
  id: 'id',
  share: 'share',
  speed_mps: 'speed',
  start: 'start',
  catalog_id: 'catalog UAV',
  endurance_min: 'endurance',
  max_accel_mps2: 'acceleration',
  climb_mps: 'climb speed',
  descent_mps: 'descent speed',
  camera: 'camera',
};

/**
 * A server field path as the form names it (issue 29, defects 7 and 9): `uavs[1].share` → "uav2 share"
 * (the row's label, not a 0-based index), `camera.altitude_m` → "Altitude", `area.coordinates[0]` →
 * "Area, polygon 1", `no_fly_zones[2]` → "No-fly zone 3", `planner_params.max_iterations` → "Planner
 * parameter max_iterations". The path itself stays for tooltips.
 */
export function fieldLabel(path: string, doc: MissionDoc | null = null): string {
  if (!path) return '';
  if (FIELD_NAMES[path]) return FIELD_NAMES[path];
  let m = /^uavs\[(\d+)\](?:\.([A-Za-z_]+)(.*))?$/.exec(path);
  if (m) {
    const i = Number(m[1]);
    const list = doc && Array.isArray(doc.uavs) ? (doc.uavs as Record<string, unknown>[]) : [];
    const id = typeof list[i]?.id === 'string' && list[i].id ? String(list[i].id) : `uav${i + 1}`;
    if (!m[2]) return id;
    const sub = m[2] === 'camera' && m[3] ? (FIELD_NAMES[`camera${m[3]}`] ?? 'camera').toLowerCase() : (UAV_FIELDS[m[2]] ?? m[2].replace(/_/g, ' '));
    return `${id} ${m[2] === 'camera' && m[3] ? `camera ${sub}` : sub}`;
  }
  m = /^(area|no_fly_zones)(?:\.coordinates)?(?:\[(\d+)\])?/.exec(path);
  if (m) {
    const n = m[2] === undefined ? null : Number(m[2]) + 1;
    if (m[1] === 'area') return n === null ? 'Area' : `Area, polygon ${n}`;
    return n === null ? 'No-fly zones' : `No-fly zone ${n}`;
  }
  m = /^planner_params\.(.+)$/.exec(path);
  if (m) return `Planner parameter ${m[1]}`;
  m = /^camera\.(.+)$/.exec(path);
  if (m) return `Camera ${m[1].replace(/_/g, ' ')}`;
  return path;
}

/** A server message for people: a leading "path: " dropped, paths inside it named as the form names them. */
export function humanMessage(path: string, message: string, doc: MissionDoc | null = null): string {
  let text = message;
  if (path && text.startsWith(`${path}: `)) text = text.slice(path.length + 2);
  return text.replace(/\b(?:uavs\[\d+\](?:\.[A-Za-z_]+)*|camera\.[A-Za-z_]+|area(?:\.coordinates)?(?:\[\d+\])+|no_fly_zones(?:\[\d+\])+|planner_params\.[A-Za-z_]+)/g, (p) => fieldLabel(p, doc));
}

// ---------------------------------------------------------------- patterns (docs/patterns.md)

export interface Corridor {
  line: Position[];
  width_m: number;
}

/** the document's corridor (line and width), or null */
export function corridorOf(doc: MissionDoc | null): Corridor | null {
  const c = doc?.corridor as { line?: GeoLike; width_m?: unknown } | undefined;
  if (!c || typeof c !== 'object' || !c.line || c.line.type !== 'LineString' || !Array.isArray(c.line.coordinates)) return null;
  const line = (c.line.coordinates as unknown[]).filter(isPosition).map((p) => [p[0], p[1]] as Position);
  return { line, width_m: typeof c.width_m === 'number' ? c.width_m : 0 };
}

/** a copy of the document as a corridor mission (the area removed), or, with line null, without one */
export function withCorridor(doc: MissionDoc, line: Position[] | null, width_m: number): MissionDoc {
  const out = { ...doc };
  if (line === null) {
    delete out.corridor;
    return out;
  }
  delete out.area;
  out.corridor = { line: { type: 'LineString', coordinates: line }, width_m };
  return out;
}

/** the pattern options the web app edits, with the server's defaults */
export interface PatternOptions {
  crosshatch: boolean;
  turnaround_m: number;
  entry: 'auto' | 'nw' | 'ne' | 'sw' | 'se';
  alternate_transects: boolean;
  capture_in_turnaround: boolean;
}
export const PATTERN_DEFAULTS: PatternOptions = {
  crosshatch: false,
  turnaround_m: 0,
  entry: 'auto',
  alternate_transects: false,
  capture_in_turnaround: false,
};

/** the document's pattern block with the defaults filled in (null: no block) */
export function patternOf(doc: MissionDoc | null): PatternOptions | null {
  const p = doc?.pattern as Record<string, unknown> | undefined;
  if (!p || typeof p !== 'object') return null;
  const out: PatternOptions = { ...PATTERN_DEFAULTS };
  if (typeof p.crosshatch === 'boolean') out.crosshatch = p.crosshatch;
  if (typeof p.turnaround_m === 'number') out.turnaround_m = p.turnaround_m;
  if (typeof p.entry === 'string' && ['auto', 'nw', 'ne', 'sw', 'se'].includes(p.entry)) out.entry = p.entry as PatternOptions['entry'];
  if (typeof p.alternate_transects === 'boolean') out.alternate_transects = p.alternate_transects;
  if (typeof p.capture_in_turnaround === 'boolean') out.capture_in_turnaround = p.capture_in_turnaround;
  return out;
}

/** a copy of the document with these pattern options: only the ones not at their default are written; the
 * other fields of the block (e.g. oblique) are kept; null removes the block */
export function withPattern(doc: MissionDoc, opts: Partial<PatternOptions> | null): MissionDoc {
  const out = { ...doc };
  if (opts === null) {
    delete out.pattern;
    return out;
  }
  const block: Record<string, unknown> = { ...((doc.pattern as Record<string, unknown> | undefined) ?? {}) };
  for (const k of Object.keys(PATTERN_DEFAULTS) as (keyof PatternOptions)[]) {
    if (!(k in opts)) continue;
    if (opts[k] === PATTERN_DEFAULTS[k]) delete block[k];
    else block[k] = opts[k];
  }
  out.pattern = block;
  return out;
}

// ---------------------------------------------------------------- structure (facade) scans

export interface StructureScan {
  footprint: PolygonCoords;
  height_m: number;
  standoff_m: number;
  top: boolean;
  safe_height_m: number;
}
export const STRUCTURE_DEFAULTS = { height_m: 30, standoff_m: 15, top: false, safe_height_m: 5 };

/** the document's structure block (footprint polygon and its numbers), or null */
export function structureOf(doc: MissionDoc | null): StructureScan | null {
  const s = doc?.structure as Record<string, unknown> | undefined;
  if (!s || typeof s !== 'object') return null;
  const polys = polygonsOf(s.footprint);
  if (polys.length !== 1) return null;
  const n = (v: unknown, d: number) => (typeof v === 'number' && Number.isFinite(v) ? v : d);
  return {
    footprint: polys[0],
    height_m: n(s.height_m, STRUCTURE_DEFAULTS.height_m),
    standoff_m: n(s.standoff_m, STRUCTURE_DEFAULTS.standoff_m),
    top: s.top === true,
    safe_height_m: n(s.safe_height_m, STRUCTURE_DEFAULTS.safe_height_m),
  };
}

/** a copy of the document as a structure scan (area and corridor removed), or, with null, without one;
 * safe_height_m is written only when it differs from the server's default */
export function withStructure(doc: MissionDoc, s: StructureScan | null): MissionDoc {
  const out = { ...doc };
  if (s === null) {
    delete out.structure;
    return out;
  }
  delete out.area;
  delete out.corridor;
  const block: Record<string, unknown> = {
    footprint: { type: 'Polygon', coordinates: [s.footprint[0]] },
    height_m: s.height_m,
    standoff_m: s.standoff_m,
    top: s.top,
  };
  if (s.safe_height_m !== STRUCTURE_DEFAULTS.safe_height_m) block.safe_height_m = s.safe_height_m;
  out.structure = block;
  return out;
}

// ---------------------------------------------------------------- obliques (pattern.oblique)

export interface ObliqueOptions {
  gimbal_pitch_deg: number;
  directions: number;
  nadir: boolean;
}
export const OBLIQUE_DEFAULTS: ObliqueOptions = { gimbal_pitch_deg: -45, directions: 4, nadir: true };

/** the document's pattern.oblique with the defaults filled in, or null */
export function obliqueOf(doc: MissionDoc | null): ObliqueOptions | null {
  const o = (doc?.pattern as Record<string, unknown> | undefined)?.oblique as Record<string, unknown> | undefined;
  if (!o || typeof o !== 'object') return null;
  return {
    gimbal_pitch_deg: typeof o.gimbal_pitch_deg === 'number' ? o.gimbal_pitch_deg : OBLIQUE_DEFAULTS.gimbal_pitch_deg,
    directions: typeof o.directions === 'number' ? o.directions : OBLIQUE_DEFAULTS.directions,
    nadir: typeof o.nadir === 'boolean' ? o.nadir : OBLIQUE_DEFAULTS.nadir,
  };
}

/** a copy of the document with pattern.oblique set (every field written), or removed (null); an emptied
 * pattern block stays (it still means "camera off in turns", docs/patterns.md) */
export function withOblique(doc: MissionDoc, o: ObliqueOptions | null): MissionDoc {
  const out = { ...doc };
  const block: Record<string, unknown> = { ...((doc.pattern as Record<string, unknown> | undefined) ?? {}) };
  if (o === null) delete block.oblique;
  else block.oblique = { gimbal_pitch_deg: o.gimbal_pitch_deg, directions: o.directions, nadir: o.nadir };
  out.pattern = block;
  return out;
}

// ---------------------------------------------------------------- wind, objective, capability shares

export interface WindInput {
  speed_mps: number;
  from_deg: number;
}

/** the document's wind, or null */
export function windOf(doc: MissionDoc | null): WindInput | null {
  const w = doc?.wind as Record<string, unknown> | undefined;
  if (!w || typeof w !== 'object' || typeof w.speed_mps !== 'number') return null;
  return { speed_mps: w.speed_mps, from_deg: typeof w.from_deg === 'number' ? w.from_deg : 0 };
}

/** a copy of the document with this wind (null or a calm one removes the block) */
export function withWind(doc: MissionDoc, w: WindInput | null): MissionDoc {
  const out = { ...doc };
  if (w === null || w.speed_mps === 0) delete out.wind;
  else out.wind = { speed_mps: w.speed_mps, from_deg: ((w.from_deg % 360) + 360) % 360 };
  return out;
}

export const OBJECTIVES = ['time', 'poc', 'turns', 'length'] as const;

/** every UAV's share "auto" (shares from capabilities, docs/mission-format.md)? */
export function sharesAuto(doc: MissionDoc | null): boolean {
  const list = Array.isArray(doc?.uavs) ? (doc.uavs as Record<string, unknown>[]) : [];
  return list.length > 0 && list.every((u) => u && u.share === 'auto');
}

/** a copy with every UAV's share "auto" (on), or with the shares removed (off: equal shares) */
export function withSharesAuto(doc: MissionDoc, on: boolean): MissionDoc {
  const list = Array.isArray(doc.uavs) ? (doc.uavs as Record<string, unknown>[]) : [];
  return {
    ...doc,
    uavs: list.map((u) => {
      const c = { ...u };
      if (on) c.share = 'auto';
      else delete c.share;
      return c;
    }),
  };
}

// ---------------------------------------------------------------- terrain (issue 31)

/** where the ground heights come from: none (flat), a DEM stored in the server, or the server's tiles */
export type TerrainSource = { kind: 'none' } | { kind: 'dem'; dem_id: number } | { kind: 'server' };

export interface TerrainInput {
  source: TerrainSource;
  follow: boolean;
  tolerance_m: number;
  max_climb_mps?: number;
  max_descent_mps?: number;
}

export const TERRAIN_DEFAULTS = { tolerance_m: 1 } as const;

/** the document's terrain block as the app edits it (a block naming a file path reads as none) */
export function terrainOf(doc: MissionDoc | null): TerrainInput {
  const t = doc?.terrain as Record<string, unknown> | undefined;
  const none: TerrainInput = { source: { kind: 'none' }, follow: true, tolerance_m: TERRAIN_DEFAULTS.tolerance_m };
  if (!t || typeof t !== 'object') return none;
  const source: TerrainSource =
    typeof t.dem_id === 'number' ? { kind: 'dem', dem_id: t.dem_id } : t.source === 'server' ? { kind: 'server' } : { kind: 'none' };
  const out: TerrainInput = {
    source,
    follow: t.mode !== 'off',
    tolerance_m: typeof t.tolerance_m === 'number' ? t.tolerance_m : TERRAIN_DEFAULTS.tolerance_m,
  };
  if (typeof t.max_climb_mps === 'number') out.max_climb_mps = t.max_climb_mps;
  if (typeof t.max_descent_mps === 'number') out.max_descent_mps = t.max_descent_mps;
  return out;
}

/** a copy of the document with this terrain block (source none removes it) */
export function withTerrain(doc: MissionDoc, t: TerrainInput): MissionDoc {
  const out = { ...doc };
  if (t.source.kind === 'none') {
    delete out.terrain;
    return out;
  }
  const block: Record<string, unknown> = t.source.kind === 'dem' ? { dem_id: t.source.dem_id } : { source: 'server' };
  block.mode = t.follow ? 'follow' : 'off';
  block.tolerance_m = t.tolerance_m;
  if (t.max_climb_mps !== undefined) block.max_climb_mps = t.max_climb_mps;
  if (t.max_descent_mps !== undefined) block.max_descent_mps = t.max_descent_mps;
  out.terrain = block;
  return out;
}
