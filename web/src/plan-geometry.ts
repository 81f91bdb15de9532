// A plan's regions and paths made ready to draw fast at any zoom (issue 11: a path of 100 000 vertices
// pans and zooms smoothly). Built once per plan, in a worker (plan-worker.ts) when the browser has one:
// - every vertex is projected once to Web Mercator pixels at zoom 0 (Leaflet's EPSG:3857: the world is
//   256 units wide; at zoom z a unit is 2^z screen pixels);
// - every vertex gets its Douglas–Peucker importance: the largest tolerance (zoom-0 units) at which DP
//   keeps it. DP's split points do not depend on the tolerance, so the simplification at zoom z with a
//   tolerance of t pixels is exactly the vertices of importance > t / 2^z: no per-zoom work, and the
//   same vertices in every tile;
// - vertices are grouped in pieces (a path chunk, a polygon) with bounding boxes, and pieces in blocks,
//   so that a tile touches only what it shows.
// No DOM and no Leaflet here: drawTile() draws into any 2D context (an OffscreenCanvas in the worker,
// a tile canvas in the page, a recording fake in the unit tests).
import { AREA_STROKE, NFZ_FILL, NFZ_FILL_OPACITY, NFZ_STROKE } from './zones.ts';
import { uavColour } from './palette.ts';

type Position = number[]; // [lon, lat]

export interface PlanImages {
  capture: string;
  trigger_distance_m: number;
  gsd_m: number | null;
  side_overlap: number;
  front_overlap: number;
  gimbal_pitch_deg: number;
  images: number;
  storage_mb: number;
  uavs: { id: string; images: number; trigger_interval_s: number; storage_mb: number }[];
}

export interface PlanJson {
  origin?: Position;
  uavs: { id: string; region?: { type: string; coordinates: Position[][][] }; start?: Position; regions?: number }[];
  cost?: { batteries_per_uav?: number; uavs?: { batteries?: number; flight_duration_min?: number }[] };
  coverage?: { uavs?: { id: string; poc?: number; pooc?: number }[] };
  /** The camera's trigger plan (docs/photogrammetry.md); only with a camera block. */
  images?: PlanImages;
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

/** The largest distance, in screen pixels, between a vertex left out and the line drawn instead. */
export const TOLERANCE_PX = 1;
/**
 * Segments per section of a ring: Douglas–Peucker runs section by section (its cost stays linear; the
 * section ends are always kept), and a tile skips the sections whose bounding box it does not touch.
 */
export const SECTION = 64;
/** Pieces per block (the first level of culling). */
const BLOCK = 32;
/** Zoom from which waypoint numbers are drawn. */
export const LABEL_ZOOM = 17;
/**
 * The numbers are decluttered on a grid of LABEL_CELL[0] × LABEL_CELL[1] screen pixels: in each cell
 * only the first waypoint (lowest UAV, then lowest number) is numbered. The choice depends on the cell
 * alone, so neighbouring tiles agree; once zoomed in far enough every waypoint has its number.
 */
export const LABEL_CELL = [44, 18] as const;
/** Waypoints per block (culling of the waypoint numbers). */
const WP_BLOCK = 256;

const MAX_LAT = 85.0511287798;

/** Longitude → Web Mercator x at zoom 0 (0..256), as Leaflet's L.CRS.EPSG3857. */
export const mercX = (lon: number): number => (lon / 360 + 0.5) * 256;
/** Latitude → Web Mercator y at zoom 0 (0 at the north edge, 256 at the south). */
export function mercY(lat: number): number {
  const s = Math.sin((Math.max(-MAX_LAT, Math.min(MAX_LAT, lat)) * Math.PI) / 180);
  return (0.5 - Math.log((1 + s) / (1 - s)) / (4 * Math.PI)) * 256;
}

/** Distance from point p to segment a–b (all [x, y] in xy at the given vertex indices). */
function segmentDistance(xy: Float64Array, p: number, a: number, b: number): number {
  const ax = xy[2 * a], ay = xy[2 * a + 1];
  const dx = xy[2 * b] - ax, dy = xy[2 * b + 1] - ay;
  let px = xy[2 * p] - ax, py = xy[2 * p + 1] - ay;
  const len2 = dx * dx + dy * dy;
  if (len2 > 0) {
    const t = Math.max(0, Math.min(1, (px * dx + py * dy) / len2));
    px -= t * dx;
    py -= t * dy;
  }
  return Math.hypot(px, py);
}

/**
 * Douglas–Peucker importance of vertices a..b (inclusive) of xy (x, y pairs): imp[a] = imp[b] =
 * Infinity; an inner vertex gets the distance at which DP splits there, capped by its ancestors' (DP
 * with tolerance t keeps a vertex iff it and every split above it are farther than t). Iterative: no
 * recursion depth limit. O(n log n) on ordinary lines, O(n²) at worst: callers bound n (dpSections).
 */
export function dpImportance(xy: Float64Array, a: number, b: number, imp: Float64Array): void {
  imp[a] = Infinity;
  imp[b] = Infinity;
  const stack: number[] = [a, b, Infinity];
  while (stack.length) {
    const cap = stack.pop()!, j = stack.pop()!, i = stack.pop()!;
    if (j - i < 2) continue;
    let best = i + 1, far = -1;
    for (let k = i + 1; k < j; k++) {
      const d = segmentDistance(xy, k, i, j);
      if (d > far) {
        far = d;
        best = k;
      }
    }
    const v = Math.min(far, cap);
    imp[best] = v;
    stack.push(i, best, v, best, j, v);
  }
}

/** dpImportance over a..b section by section (SECTION segments each; the section ends are always kept). */
export function dpSections(xy: Float64Array, a: number, b: number, imp: Float64Array): void {
  for (let s = a; s < b; s += SECTION) dpImportance(xy, s, Math.min(s + SECTION, b), imp);
  if (a === b) imp[a] = Infinity;
}

/** The vertices of a..b kept at a tolerance of `tol` zoom-0 units (indices, in order). */
export function keptVertices(imp: Float64Array, a: number, b: number, tol: number): number[] {
  const out: number[] = [];
  for (let k = a; k <= b; k++) if (imp[k] > tol) out.push(k);
  return out;
}

export interface LayerStyle {
  color: string;
  /** stroke width in CSS pixels */
  weight: number;
  opacity: number;
  dash?: number[];
  /** polygons: filled with this opacity (even-odd), then stroked */
  fillOpacity?: number;
  /** the fill's colour if not `color` */
  fillColor?: string;
}

/**
 * One style's geometry: rings (vertex ranges, closed for polygons) grouped in pieces (one polygon, or
 * one path part), with bounding boxes per section of a ring, per piece and per block of pieces.
 */
export interface Layer {
  style: LayerStyle;
  closed: boolean;
  /** per ring: first and last vertex index (inclusive) */
  rings: Int32Array;
  /** piece p owns rings pieceRings[p] .. pieceRings[p + 1] - 1 */
  pieceRings: Int32Array;
  /** ring r's sections (vertices a + SECTION·i .. min(a + SECTION·(i + 1), b)) have the boxes ringSections[r] .. ringSections[r + 1] - 1 */
  ringSections: Int32Array;
  /** minx, miny, maxx, maxy per section, zoom-0 units */
  sectionBoxes: Float64Array;
  /** minx, miny, maxx, maxy per piece, zoom-0 units */
  pieceBoxes: Float64Array;
  /** the same per block of BLOCK pieces */
  blockBoxes: Float64Array;
}

export interface Geometry {
  /** x, y per vertex, zoom-0 Web Mercator units */
  xy: Float64Array;
  imp: Float64Array;
  /** in drawing order: the area, no-fly zones, regions, coverage paths, transit paths */
  layers: Layer[];
  /** the waypoints (distinct consecutive path vertices) of all UAVs: x, y per waypoint, zoom-0 units */
  wp: Float64Array;
  /** UAV u's waypoints are wpStart[u] .. wpStart[u + 1] - 1, numbered from 1 */
  wpStart: Int32Array;
  /** minx, miny, maxx, maxy per block of WP_BLOCK waypoints */
  wpBoxes: Float64Array;
  /** per UAV: its colour */
  colours: string[];
}

export interface UavSummary {
  id: string;
  colour: string;
  /** region polygons, path parts, distinct consecutive path vertices */
  polygons: number;
  paths: number;
  waypoints: number;
  /** [lat, lng] */
  start: [number, number] | null;
  end: [number, number] | null;
}

export interface PlanSummary {
  /** [[south, west], [north, east]] of the area and the paths, or null if empty */
  bounds: [[number, number], [number, number]] | null;
  uavs: UavSummary[];
}

/** The bounding box of vertices a..b (inclusive) of xy, stored as box i of out. */
function box(xy: Float64Array, a: number, b: number, out: Float64Array, i: number): void {
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (let k = a; k <= b; k++) {
    const x = xy[2 * k], y = xy[2 * k + 1];
    if (x < x0) x0 = x;
    if (x > x1) x1 = x;
    if (y < y0) y0 = y;
    if (y > y1) y1 = y;
  }
  out[4 * i] = x0;
  out[4 * i + 1] = y0;
  out[4 * i + 2] = x1;
  out[4 * i + 3] = y1;
}

/** n boxes, box j the union of boxes[range(j)[0] .. range(j)[1] - 1]. */
function unionBoxes(boxes: Float64Array, n: number, range: (j: number) => [number, number]): Float64Array {
  const out = new Float64Array(4 * n);
  for (let j = 0; j < n; j++) {
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    const [a, b] = range(j);
    for (let i = a; i < b; i++) {
      x0 = Math.min(x0, boxes[4 * i]);
      y0 = Math.min(y0, boxes[4 * i + 1]);
      x1 = Math.max(x1, boxes[4 * i + 2]);
      y1 = Math.max(y1, boxes[4 * i + 3]);
    }
    out.set([x0, y0, x1, y1], 4 * j);
  }
  return out;
}

/** Accumulates vertices and rings into layers. */
class Builder {
  private x: number[] = [];
  readonly layers: { style: LayerStyle; closed: boolean; rings: number[]; pieceRings: number[] }[] = [];

  layer(style: LayerStyle, closed: boolean): number {
    this.layers.push({ style, closed, rings: [], pieceRings: [0] });
    return this.layers.length - 1;
  }
  /** Adds pts[from..to] ([lon, lat] positions) as a ring of the open piece of layer l. */
  ring(l: number, pts: Position[], from = 0, to = pts.length - 1): void {
    const a = this.x.length / 2;
    for (let k = from; k <= to; k++) this.x.push(mercX(pts[k][0]), mercY(pts[k][1]));
    this.layers[l].rings.push(a, a + (to - from));
  }
  endPiece(l: number): void {
    const L = this.layers[l];
    if (L.pieceRings[L.pieceRings.length - 1] !== L.rings.length / 2) L.pieceRings.push(L.rings.length / 2);
  }
  build(wps: number[][], colours: string[]): Geometry {
    const xy = Float64Array.from(this.x);
    const imp = new Float64Array(xy.length / 2);
    const layers: Layer[] = this.layers.map((L) => {
      const rings = Int32Array.from(L.rings);
      for (let r = 0; r < rings.length; r += 2) dpSections(xy, rings[r], rings[r + 1], imp);
      const pieceRings = Int32Array.from(L.pieceRings);
      const nr = rings.length / 2;
      const ringSections = new Int32Array(nr + 1);
      for (let r = 0; r < nr; r++) ringSections[r + 1] = ringSections[r] + Math.max(1, Math.ceil((rings[2 * r + 1] - rings[2 * r]) / SECTION));
      const sectionBoxes = new Float64Array(4 * ringSections[nr]);
      for (let r = 0; r < nr; r++)
        for (let i = ringSections[r], a = rings[2 * r]; i < ringSections[r + 1]; i++, a += SECTION) box(xy, a, Math.min(a + SECTION, rings[2 * r + 1]), sectionBoxes, i);
      const n = pieceRings.length - 1;
      const pieceBoxes = unionBoxes(sectionBoxes, n, (p) => [ringSections[pieceRings[p]], ringSections[pieceRings[p + 1]]]);
      const blockBoxes = unionBoxes(pieceBoxes, Math.ceil(n / BLOCK), (b) => [b * BLOCK, Math.min(n, (b + 1) * BLOCK)]);
      return { style: L.style, closed: L.closed, rings, pieceRings, ringSections, sectionBoxes, pieceBoxes, blockBoxes };
    });
    const wpStart = new Int32Array(wps.length + 1);
    wps.forEach((l, u) => (wpStart[u + 1] = wpStart[u] + l.length / 2));
    const wp = new Float64Array(2 * wpStart[wps.length]);
    wps.forEach((l, u) => {
      for (let k = 0; 2 * k < l.length; k++) {
        wp[2 * (wpStart[u] + k)] = mercX(l[2 * k + 1]);
        wp[2 * (wpStart[u] + k) + 1] = mercY(l[2 * k]);
      }
    });
    const n = wp.length / 2;
    const wpBoxes = new Float64Array(4 * Math.ceil(n / WP_BLOCK));
    for (let b = 0; b * WP_BLOCK < n; b++) box(wp, b * WP_BLOCK, Math.min(n, (b + 1) * WP_BLOCK) - 1, wpBoxes, b);
    return { xy, imp, layers, wp, wpStart, wpBoxes, colours };
  }
}

/**
 * The plan's drawable geometry and what the page needs besides (bounds, counts per UAV, start and
 * return points). Styles as before (plan-layers.ts): the area outlined, no-fly zones shaded with a
 * dashed outline, regions shaded in the UAV's colour (the CLI's palette), coverage solid, transit dashed.
 */
export function buildPlanGeometry(plan: PlanJson, paths: PathsGeoJson): { geometry: Geometry; summary: PlanSummary } {
  const b = new Builder();
  let s = Infinity, w = Infinity, n = -Infinity, e = -Infinity;
  const extend = (p: Position) => {
    if (p[1] < s) s = p[1];
    if (p[1] > n) n = p[1];
    if (p[0] < w) w = p[0];
    if (p[0] > e) e = p[0];
  };
  const ll = (p: Position): [number, number] => [p[1], p[0]];

  // the area (outlined) and its no-fly zones (shaded, dashed outline)
  const area = b.layer({ color: AREA_STROKE, weight: 1.5, opacity: 1 }, true);
  // dash patterns with butt caps: Leaflet's round-capped [4, 3] and [6, 5] (drawTile); no-fly zones
  // red as in the Define and Fly tabs (zones.ts)
  const nfz = b.layer({ color: NFZ_STROKE, weight: 1.5, opacity: 1, dash: [5.5, 1.5], fillColor: NFZ_FILL, fillOpacity: NFZ_FILL_OPACITY }, true);
  for (const f of paths.features) {
    if (!f.properties.role || f.geometry.type !== 'Polygon') continue;
    const l = f.properties.role === 'no_fly_zone' ? nfz : area;
    for (const r of f.geometry.coordinates as Position[][])
      if (r.length) {
        r.forEach(extend);
        b.ring(l, r);
      }
    b.endPiece(l);
  }

  const index = new Map<string, number>();
  plan.uavs.forEach((u, i) => index.set(u.id, i));
  const uavs: UavSummary[] = plan.uavs.map((u, i) => ({ id: u.id, colour: uavColour(i), polygons: 0, paths: 0, waypoints: 0, start: u.start ? ll(u.start) : null, end: null }));

  plan.uavs.forEach((u, i) => {
    if (!u.region?.coordinates) return;
    const c = uavColour(i);
    const l = b.layer({ color: c, weight: 1, opacity: 0.6, fillOpacity: 0.22 }, true);
    for (const poly of u.region.coordinates) {
      for (const r of poly) if (r.length) b.ring(l, r);
      b.endPiece(l);
      uavs[i].polygons++;
    }
  });

  const parts = paths.features
    .filter((f) => f.properties.uav !== undefined && f.geometry.type === 'LineString')
    .sort((a, c) => (a.properties.part ?? 0) - (c.properties.part ?? 0));
  const coverage = plan.uavs.map((_, i) => b.layer({ color: uavColour(i), weight: 2.5, opacity: 1 }, false));
  const transit = plan.uavs.map((_, i) => b.layer({ color: uavColour(i), weight: 2, opacity: 0.85, dash: [8, 3] }, false));
  const wps: number[][] = plan.uavs.map(() => []);
  for (const f of parts) {
    const i = index.get(f.properties.uav!);
    if (i === undefined) continue;
    const pts = f.geometry.coordinates as Position[];
    if (!pts.length) continue;
    uavs[i].paths++;
    const l = f.properties.kind === 'transit' ? transit[i] : coverage[i];
    b.ring(l, pts);
    b.endPiece(l);
    const list = wps[i];
    for (const p of pts) {
      extend(p);
      const m = list.length;
      if (m && list[m - 2] === p[1] && list[m - 1] === p[0]) continue;
      list.push(p[1], p[0]);
    }
  }
  uavs.forEach((u, i) => {
    const list = wps[i];
    u.waypoints = list.length / 2;
    if (list.length) {
      u.start ??= [list[0], list[1]];
      u.end = [list[list.length - 2], list[list.length - 1]];
    }
  });
  return {
    geometry: b.build(
      wps,
      uavs.map((u) => u.colour),
    ),
    summary: { bounds: s <= n ? [[s, w], [n, e]] : null, uavs },
  };
}

/** plan.json and paths.geojson (bytes) → the geometry, the summary, and plan.json without its regions (for the page). */
export function parsePlan(planBytes: ArrayBuffer, pathsBytes: ArrayBuffer): { geometry: Geometry; summary: PlanSummary; plan: PlanJson } {
  const dec = new TextDecoder();
  const plan = JSON.parse(dec.decode(planBytes)) as PlanJson;
  const { geometry, summary } = buildPlanGeometry(plan, JSON.parse(dec.decode(pathsBytes)) as PathsGeoJson);
  return { geometry, summary, plan: { ...plan, uavs: plan.uavs.map(({ region: _region, ...u }) => u) } };
}

/** The part of CanvasRenderingContext2D that drawTile uses. */
export interface Ctx2D {
  setTransform(a: number, b: number, c: number, d: number, e: number, f: number): void;
  clearRect(x: number, y: number, w: number, h: number): void;
  beginPath(): void;
  moveTo(x: number, y: number): void;
  lineTo(x: number, y: number): void;
  fill(rule?: CanvasFillRule): void;
  stroke(): void;
  globalAlpha: number;
  fillStyle: string | CanvasGradient | CanvasPattern;
  strokeStyle: string | CanvasGradient | CanvasPattern;
  lineWidth: number;
  lineJoin: CanvasLineJoin;
  lineCap: CanvasLineCap;
  font: string;
  textAlign: CanvasTextAlign;
  textBaseline: CanvasTextBaseline;
  fillText(t: string, x: number, y: number): void;
  measureText(t: string): { width: number };
  fillRect(x: number, y: number, w: number, h: number): void;
  strokeRect(x: number, y: number, w: number, h: number): void;
}

/** The numbered waypoints that the tile (z, x, y) shows: [uav, index in its path, x, y in tile pixels], in drawing order. */
export function tileLabels(g: Geometry, z: number, x: number, y: number, size: number): [number, number, number, number][] {
  if (z < LABEL_ZOOM) return [];
  const scale = 2 ** z;
  const [cw, ch] = LABEL_CELL;
  const margin = 48; // a label's half width, at most
  // whole cells around the tile and its margin: each cell's first waypoint is decided on all of it
  const cx0 = Math.floor((x * size - margin) / cw), cx1 = Math.floor(((x + 1) * size + margin) / cw);
  const cy0 = Math.floor((y * size - margin) / ch), cy1 = Math.floor(((y + 1) * size + margin) / ch);
  const wx0 = (cx0 * cw) / scale, wx1 = ((cx1 + 1) * cw) / scale, wy0 = (cy0 * ch) / scale, wy1 = ((cy1 + 1) * ch) / scale;
  const first = new Map<number, [number, number, number, number]>();
  const { wp, wpStart, wpBoxes } = g;
  for (let u = 0; u + 1 < wpStart.length; u++)
    for (let b = Math.floor(wpStart[u] / WP_BLOCK); b * WP_BLOCK < wpStart[u + 1]; b++) {
      if (wpBoxes[4 * b] >= wx1 || wpBoxes[4 * b + 2] < wx0 || wpBoxes[4 * b + 1] >= wy1 || wpBoxes[4 * b + 3] < wy0) continue;
      for (let k = Math.max(wpStart[u], b * WP_BLOCK); k < Math.min(wpStart[u + 1], (b + 1) * WP_BLOCK); k++) {
        const px = wp[2 * k] * scale, py = wp[2 * k + 1] * scale;
        const cx = Math.floor(px / cw), cy = Math.floor(py / ch);
        if (cx < cx0 || cx > cx1 || cy < cy0 || cy > cy1) continue;
        const key = (cy - cy0) * (cx1 - cx0 + 1) + (cx - cx0);
        if (!first.has(key)) first.set(key, [u, k - wpStart[u], px - x * size, py - y * size]);
      }
    }
  return [...first.values()].sort((a, b) => a[0] - b[0] || a[1] - b[1]);
}

/** Draws waypoint numbers as the app's labels: a white box, the UAV's colour as its border. */
function drawLabels(ctx: Ctx2D, g: Geometry, labels: [number, number, number, number][]): void {
  ctx.globalAlpha = 1;
  ctx.lineWidth = 1.5;
  ctx.font = '10px ui-monospace, monospace';
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  for (const [u, k, x, y] of labels) {
    const text = String(k + 1);
    const w = Math.ceil(ctx.measureText(text).width) + 6, h = 13;
    ctx.fillStyle = '#fff';
    ctx.fillRect(Math.round(x - w / 2), Math.round(y - h / 2), w, h);
    ctx.strokeStyle = g.colours[u];
    ctx.strokeRect(Math.round(x - w / 2), Math.round(y - h / 2), w, h);
    ctx.fillStyle = '#1d2733';
    ctx.fillText(text, Math.round(x), Math.round(y) + 0.5);
  }
}

/** The part [t0, t1] (fractions of its length) of the segment p + t·d inside the rectangle r, or null. */
export function clipSegment(px: number, py: number, dx: number, dy: number, r: readonly number[]): [number, number] | null {
  let t0 = 0, t1 = 1;
  // Liang–Barsky: each side of the rectangle as p·t <= q
  const sides: [number, number][] = [
    [-dx, px - r[0]],
    [dx, r[2] - px],
    [-dy, py - r[1]],
    [dy, r[3] - py],
  ];
  for (const [p, q] of sides) {
    if (p === 0) {
      if (q < 0) return null;
    } else if (p < 0) t0 = Math.max(t0, q / p);
    else t1 = Math.min(t1, q / p);
    if (t0 > t1) return null;
  }
  return [t0, t1];
}

/**
 * Traces the dashes of a line through the points pts (x, y pairs, tile pixels): `dash` = [on, off]
 * pixels, the pattern starting at the first point (whatever the tile, so that the dashes of
 * neighbouring tiles meet), only where the line crosses the rectangle r. Returns the dashes traced.
 */
export function traceDashes(ctx: Pick<Ctx2D, 'moveTo' | 'lineTo'>, pts: ArrayLike<number>, dash: readonly number[], r: readonly number[]): number {
  const on = dash[0], period = dash[0] + dash[1];
  let phase = 0, n = 0;
  for (let k = 2; k + 1 < pts.length; k += 2) {
    const px = pts[k - 2], py = pts[k - 1], dx = pts[k] - px, dy = pts[k + 1] - py;
    const len = Math.hypot(dx, dy);
    if (len === 0) continue;
    const c = clipSegment(px, py, dx, dy, r);
    if (!c) {
      phase = (phase + len) % period;
      continue;
    }
    let d = c[0] * len;
    const end = c[1] * len;
    phase = (phase + d) % period;
    let down = false;
    while (d < end - 1e-9) {
      const step = Math.min((phase < on ? on : period) - phase, end - d);
      if (phase < on) {
        if (!down) ctx.moveTo(px + (dx * d) / len, py + (dy * d) / len);
        down = true;
        ctx.lineTo(px + (dx * (d + step)) / len, py + (dy * (d + step)) / len);
        n++;
      } else down = false;
      d += step;
      phase += step;
      if (phase >= period - 1e-9) phase = 0;
    }
    phase = (phase + len - end) % period;
  }
  return n;
}

/**
 * Draws the tile (x, y) of zoom z, `size` CSS pixels square (Leaflet's GridLayer coordinates), at
 * `dpr` device pixels per CSS pixel, with the vertices kept at TOLERANCE_PX, and from LABEL_ZOOM the
 * waypoint numbers. Returns the number of vertices, dashes and numbers drawn (0: an empty tile).
 *
 * No closePath(): Chromium's canvas takes seconds for tens of thousands of closed subpaths (quadratic,
 * bench/web), and a GeoJSON ring ends on its first vertex anyway; fill() closes each subpath itself.
 */
export function drawTile(ctx: Ctx2D, g: Geometry, z: number, x: number, y: number, size: number, dpr = 1, tolPx = TOLERANCE_PX): number {
  const scale = 2 ** z;
  const ox = x * size, oy = y * size;
  const thr = tolPx / scale;
  const { xy, imp } = g;
  let drawn = 0;
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  // bevel joins and butt caps: within a pixel of round ones at these widths (the dash patterns are
  // lengthened by the width to look as round-capped ones), and half the rasterising time (bench/web)
  ctx.lineJoin = 'bevel';
  ctx.lineCap = 'butt';
  const pts: number[] = [];
  for (const L of g.layers) {
    const st = L.style;
    // the tile widened by half a stroke and a pixel: in pixels, and in zoom-0 units
    const mp = st.weight / 2 + 1;
    const rect = [-mp, -mp, size + mp, size + mp];
    const x0 = (ox - mp) / scale, y0 = (oy - mp) / scale, x1 = (ox + size + mp) / scale, y1 = (oy + size + mp) / scale;
    const out = (bx: Float64Array, i: number) => bx[4 * i] > x1 || bx[4 * i + 2] < x0 || bx[4 * i + 1] > y1 || bx[4 * i + 3] < y0;
    const rings: number[] = [];
    const pieces = L.pieceRings.length - 1;
    for (let bl = 0; bl * BLOCK < pieces; bl++) {
      if (out(L.blockBoxes, bl)) continue;
      for (let p = bl * BLOCK; p < Math.min(pieces, (bl + 1) * BLOCK); p++)
        if (!out(L.pieceBoxes, p)) for (let r = L.pieceRings[p]; r < L.pieceRings[p + 1]; r++) rings.push(r);
    }
    if (!rings.length) continue;
    const fill = st.fillOpacity !== undefined;
    // the rings as lines (or polygons): a section the tile does not touch is left out of a line, and
    // a polygon's ring goes straight to the section's end instead (a chord that, like the section,
    // lies wholly beyond one side of the tile: what is filled and stroked in the tile is unchanged)
    const trace = () => {
      ctx.beginPath();
      for (const r of rings) {
        const a = L.rings[2 * r], e = L.rings[2 * r + 1];
        let pen = false; // false: the next vertex starts a subpath
        for (let i = L.ringSections[r], s = a; i < L.ringSections[r + 1]; i++, s += SECTION) {
          const t = Math.min(s + SECTION, e);
          if (out(L.sectionBoxes, i)) {
            if (L.closed) {
              if (!pen) ctx.moveTo(xy[2 * s] * scale - ox, xy[2 * s + 1] * scale - oy);
              ctx.lineTo(xy[2 * t] * scale - ox, xy[2 * t + 1] * scale - oy);
              pen = true;
              drawn++;
            } else pen = false;
            continue;
          }
          if (!pen) {
            ctx.moveTo(xy[2 * s] * scale - ox, xy[2 * s + 1] * scale - oy);
            drawn++;
            pen = true;
          }
          for (let k = s + 1; k <= t; k++)
            if (imp[k] > thr) {
              ctx.lineTo(xy[2 * k] * scale - ox, xy[2 * k + 1] * scale - oy);
              drawn++;
            }
        }
      }
    };
    if (fill || !st.dash) trace();
    if (fill) {
      ctx.globalAlpha = st.fillOpacity!;
      ctx.fillStyle = st.fillColor ?? st.color;
      ctx.fill('evenodd');
    }
    if (st.dash) {
      // dashes traced here, as short solid lines: the canvas' own dashing costs ten times more to
      // rasterise; the pattern starts at each ring's first vertex, so tiles agree
      ctx.beginPath();
      for (const r of rings) {
        pts.length = 0;
        for (let k = L.rings[2 * r]; k <= L.rings[2 * r + 1]; k++)
          if (imp[k] > thr || k === L.rings[2 * r]) pts.push(xy[2 * k] * scale - ox, xy[2 * k + 1] * scale - oy);
        drawn += traceDashes(ctx, pts, st.dash, rect);
      }
    }
    ctx.globalAlpha = st.opacity;
    ctx.strokeStyle = st.color;
    ctx.lineWidth = st.weight;
    ctx.stroke();
  }
  const labels = tileLabels(g, z, x, y, size);
  drawLabels(ctx, g, labels);
  return drawn + labels.length;
}
