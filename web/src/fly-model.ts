// The Fly tab's data (docs/flights.md) and the logic that does not touch the DOM: the coverage
// waypoints of a plan in flight order (the global indices of docs/sorties.md), waypoint status strings,
// the failure option of a simulated fleet, labels, and the replay of a flight log (positions and
// waypoint statuses at any time). Unit-tested in tests/unit/fly-model.test.mjs.
import type { PathsGeoJson } from './plan-geometry.ts';

export type FlightState = 'created' | 'uploading' | 'ready' | 'flying' | 'paused' | 'done' | 'aborted';

export interface FlightPosition {
  lon: number;
  lat: number;
  alt_m?: number;
  speed_mps?: number;
  heading_deg?: number;
}

export interface FlightMission {
  kind: 'sortie' | 'reassigned' | 'resume' | string;
  index?: number;
  reassignment?: number;
  first_waypoint?: number;
  last_waypoint?: number;
  state?: string;
  waypoints?: string;
  path?: number[][];
}

export interface FlightUav {
  uav: string;
  endpoint?: string;
  sysid?: number;
  phase: string;
  link?: { state: string; last_heard?: string | null; rx?: number; tx?: number };
  position?: FlightPosition | null;
  armed?: boolean;
  mode?: string;
  battery_pct?: number | null;
  band?: string;
  progress?: number;
  eta_s?: number | null;
  sortie?: number;
  sorties?: number;
  waypoints?: string;
  missions?: FlightMission[];
  trail?: number[][];
  /** the task manager's waypoint retries (docs/flights.md#waypoint-retries) */
  retries?: { waypoint?: number | null; count?: number; total?: number };
}

export interface FlightAlert {
  kind: string;
  uav?: string;
  other?: string | null;
  message?: string;
  since?: string;
  active?: boolean;
}

export interface FlightReassignment {
  id: number;
  failed_uav: string;
  state: string;
  at?: string;
  last_reached?: number;
  remaining_waypoints?: number;
  area_m2?: number;
  to?: { uav: string; waypoints?: number; length_m?: number }[];
}

export interface Flight {
  id: number;
  plan_id: number;
  mission_id?: number;
  state: FlightState;
  simulated?: boolean;
  created?: string;
  updated?: string;
  config?: Record<string, unknown>;
  uavs: FlightUav[];
  alerts?: FlightAlert[];
  reassignments?: FlightReassignment[];
}

export interface LogRecord {
  seq: number;
  t: string | number;
  uav: string;
  kind: string;
  data: Record<string, unknown>;
}

export interface FlightCoverage {
  flown_poc: number | null;
  planned_poc: number | null;
  bounds: [[number, number], [number, number]] | null;
  updated?: string;
}

export const flightEnded = (s: string): boolean => s === 'done' || s === 'aborted';

export type Status = 'P' | 'C' | 'R' | 'S';

/** Hong et al. Fig. 14: not yet reached grey, current yellow, reached green; skipped (not flown by this UAV) red. */
export const STATUS_COLOUR: Record<Status, string> = {
  P: '#a0a8b2',
  C: '#ffd400',
  R: '#00b140',
  S: '#e8112d',
};

export const STATUS_NAME: Record<Status, string> = { P: 'pending', C: 'current', R: 'reached', S: 'skipped' };

/** A status character, from a character or a word ("reached", "R", "current", ...); null when unknown. */
export function statusOf(v: unknown): Status | null {
  if (typeof v !== 'string' || !v) return null;
  const c = v[0].toUpperCase();
  return c === 'P' || c === 'C' || c === 'R' || c === 'S' ? c : null;
}

/** The number of waypoints with status `s` in a status string. */
export function countStatus(statuses: string | undefined, s: Status): number {
  if (!statuses) return 0;
  let n = 0;
  for (let i = 0; i < statuses.length; i++) if (statuses.charCodeAt(i) === s.charCodeAt(0)) n++;
  return n;
}

/** A UAV's planned lines, [lat, lon]. */
export interface UavLines {
  /** coverage waypoints in flight order: index = global waypoint index */
  waypoints: [number, number][];
  coverage: [number, number][][];
  transit: [number, number][][];
}

/**
 * Each UAV's coverage waypoints [lat, lon] in flight order: the vertices of its coverage parts in part
 * order (paths.geojson "part"), every vertex counted, as sorties::coverage_waypoints numbers them.
 * Also each UAV's transit lines, for drawing.
 */
export function planWaypoints(paths: PathsGeoJson): Map<string, UavLines> {
  const out = new Map<string, UavLines>();
  const groups = new Map<string, { part: number; kind: string; line: [number, number][] }[]>();
  paths.features.forEach((f, order) => {
    const id = f.properties?.uav;
    if (typeof id !== 'string' || f.geometry?.type !== 'LineString') return;
    let g = groups.get(id);
    if (!g) groups.set(id, (g = []));
    const line = (f.geometry.coordinates as number[][]).filter((p) => Array.isArray(p) && p.length >= 2).map((p) => [p[1], p[0]] as [number, number]);
    g.push({ part: f.properties.part ?? order, kind: f.properties.kind ?? 'coverage', line });
  });
  for (const [id, g] of groups) {
    const u: UavLines = { waypoints: [], coverage: [], transit: [] };
    for (const p of g.sort((a, b) => a.part - b.part)) {
      if (p.kind === 'transit') u.transit.push(p.line);
      else {
        u.coverage.push(p.line);
        for (const q of p.line) u.waypoints.push(q);
      }
    }
    out.set(id, u);
  }
  return out;
}

/** The indices where two status strings differ (all of `next` when the lengths differ). */
export function changedIndices(prev: string, next: string): number[] {
  const out: number[] = [];
  if (prev.length !== next.length) {
    for (let i = 0; i < next.length; i++) out.push(i);
    return out;
  }
  for (let i = 0; i < next.length; i++) if (prev.charCodeAt(i) !== next.charCodeAt(i)) out.push(i);
  return out;
}

/**
 * The failure of a simulated vehicle as `uavcover simulate --fail`: "ID@FRACTION[:KIND]" with the UAV's
 * 1-based position and the fraction of its mission; null when no failure is asked for. Throws on bad input.
 */
export function failSpec(position: number, percent: number, kind: string): string | null {
  if (!(position >= 1)) return null;
  if (!Number.isInteger(position)) throw new Error('the failing UAV: must be one of the plan’s UAVs');
  if (!Number.isFinite(percent) || percent < 0 || percent > 100) throw new Error('the failure point: must be between 0 and 100 %');
  const fraction = Math.round(percent * 10) / 1000;
  return `${position}@${fraction}${kind ? `:${kind}` : ''}`;
}

/** "3 min 05 s", "45 s", "—". */
export function formatEta(s: number | null | undefined): string {
  if (s === null || s === undefined || !Number.isFinite(s) || s < 0) return '—';
  const t = Math.round(s);
  if (t < 60) return `${t} s`;
  const h = Math.floor(t / 3600);
  const m = Math.floor((t % 3600) / 60);
  const sec = String(t % 60).padStart(2, '0');
  return h > 0 ? `${h} h ${String(m).padStart(2, '0')} min` : `${m} min ${sec} s`;
}

/** The time of a record or snapshot field in Unix milliseconds (ISO text or a number of ms); NaN when unknown. */
export function timeMs(t: unknown): number {
  if (typeof t === 'number') return t;
  if (typeof t === 'string') return Date.parse(t);
  return NaN;
}

/** The initial bearing from a to b ([lat, lon], degrees), clockwise from north, 0..360. */
export function bearing(a: readonly [number, number], b: readonly [number, number]): number {
  const r = Math.PI / 180;
  const y = Math.sin((b[1] - a[1]) * r) * Math.cos(b[0] * r);
  const x = Math.cos(a[0] * r) * Math.sin(b[0] * r) - Math.sin(a[0] * r) * Math.cos(b[0] * r) * Math.cos((b[1] - a[1]) * r);
  return ((Math.atan2(y, x) / r) % 360 + 360) % 360;
}

// ---------------------------------------------------------------- replay

export interface TrackSample {
  t: number;
  lat: number;
  lon: number;
  heading: number | null;
  battery: number | null;
}

export interface ReplayUav {
  uav: string;
  track: TrackSample[];
  /** waypoint status changes, in time order */
  changes: { t: number; index: number; status: Status }[];
  /** the number of coverage waypoints (the highest index seen + 1 when larger than the plan's) */
  waypoints: number;
}

export interface Replay {
  t0: number;
  t1: number;
  uavs: Map<string, ReplayUav>;
  /** the other records (commands, alerts, reassignments, state), for the event list */
  events: { t: number; uav: string; kind: string; text: string }[];
}

const num = (v: unknown): number | null => (typeof v === 'number' && Number.isFinite(v) ? v : null);

/**
 * A replay from the flight log's records (any order; seq decides ties). Telemetry gives positions
 * (data.lat/lon, or data.position.lat/lon), waypoint records give status changes (data.waypoint or
 * data.index, data.status). `planned`: each UAV's number of coverage waypoints.
 */
export function buildReplay(records: LogRecord[], planned: Map<string, number>): Replay {
  const sorted = records
    .map((r) => ({ r, t: timeMs(r.t) }))
    .filter((x) => Number.isFinite(x.t))
    .sort((a, b) => a.t - b.t || a.r.seq - b.r.seq);
  const uavs = new Map<string, ReplayUav>();
  const uav = (id: string) => {
    let u = uavs.get(id);
    if (!u) uavs.set(id, (u = { uav: id, track: [], changes: [], waypoints: planned.get(id) ?? 0 }));
    return u;
  };
  for (const id of planned.keys()) uav(id);
  const events: Replay['events'] = [];
  let t0 = Infinity;
  let t1 = -Infinity;
  for (const { r, t } of sorted) {
    t0 = Math.min(t0, t);
    t1 = Math.max(t1, t);
    const d = (r.data ?? {}) as Record<string, unknown>;
    if (r.kind === 'telemetry' && r.uav) {
      const p = (typeof d.position === 'object' && d.position !== null ? d.position : d) as Record<string, unknown>;
      const lat = num(p.lat);
      const lon = num(p.lon);
      if (lat === null || lon === null) continue;
      uav(r.uav).track.push({ t, lat, lon, heading: num(p.heading_deg) ?? num(d.heading_deg), battery: num(d.battery_pct) });
    } else if (r.kind === 'waypoint' && r.uav) {
      if (d.reassignment !== undefined && d.reassignment !== null) continue; // a reassigned mission's own waypoints
      const index = num(d.waypoint) ?? num(d.index);
      const status = statusOf(d.status);
      if (index === null || index < 0 || !Number.isInteger(index) || status === null) continue;
      const u = uav(r.uav);
      u.changes.push({ t, index, status });
      u.waypoints = Math.max(u.waypoints, index + 1);
    } else if (r.kind !== 'telemetry' && r.kind !== 'waypoint') {
      const text = typeof d.message === 'string' ? d.message : typeof d.command === 'string' ? d.command : typeof d.state === 'string' ? d.state : JSON.stringify(d);
      events.push({ t, uav: r.uav, kind: r.kind, text });
    }
  }
  if (!Number.isFinite(t0)) t0 = t1 = 0;
  return { t0, t1, uavs, events };
}

/** The first index i with a[i].t > t (binary search over items sorted by t). */
function upper(a: readonly { t: number }[], t: number): number {
  let lo = 0;
  let hi = a.length;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (a[mid].t <= t) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/**
 * The UAV's position at time t, linearly interpolated between telemetry samples (the first sample
 * before the track starts, the last after it ends), its heading (the sample's, else the direction of
 * travel) and `count`, the samples up to t (the trail). Null without telemetry.
 */
export function positionAt(u: ReplayUav, t: number): { lat: number; lon: number; heading: number; count: number } | null {
  const a = u.track;
  if (!a.length) return null;
  const i = upper(a, t);
  if (i === 0) return { lat: a[0].lat, lon: a[0].lon, heading: a[0].heading ?? 0, count: 1 };
  const p = a[i - 1];
  if (i === a.length) return { lat: p.lat, lon: p.lon, heading: p.heading ?? (i > 1 ? bearing([a[i - 2].lat, a[i - 2].lon], [p.lat, p.lon]) : 0), count: i };
  const q = a[i];
  const f = q.t > p.t ? (t - p.t) / (q.t - p.t) : 0;
  const lat = p.lat + f * (q.lat - p.lat);
  const lon = p.lon + f * (q.lon - p.lon);
  const moved = p.lat !== q.lat || p.lon !== q.lon;
  return { lat, lon, heading: p.heading ?? (moved ? bearing([p.lat, p.lon], [q.lat, q.lon]) : 0), count: i };
}

/** The UAV's waypoint statuses at time t (every waypoint pending before its first change). */
export function statusesAt(u: ReplayUav, t: number): string {
  const s: string[] = new Array(u.waypoints).fill('P');
  const end = upper(u.changes, t);
  for (let k = 0; k < end; k++) {
    const c = u.changes[k];
    if (c.index < s.length) s[c.index] = c.status;
  }
  return s.join('');
}

/**
 * A UAV's work in a flight: its own coverage waypoints and those reassigned to it (missions of kind
 * `reassigned`, statuses in their own `waypoints`). Progress counts both (issue 29, defect 5: a helper
 * that finished its own 13 waypoints and flies 15 reassigned ones is not at 100 %).
 */
export function uavWork(u: Pick<FlightUav, 'waypoints' | 'missions'>): { ownReached: number; own: number; extraReached: number; extra: number } {
  const own = u.waypoints?.length ?? 0;
  const ownReached = countStatus(u.waypoints, 'R');
  let extra = 0;
  let extraReached = 0;
  for (const m of u.missions ?? []) {
    if (m.kind !== 'reassigned' || typeof m.waypoints !== 'string') continue;
    extra += m.waypoints.length;
    extraReached += countStatus(m.waypoints, 'R');
  }
  return { ownReached, own, extraReached, extra };
}

/** "100.0 % (13/13)", or with reassigned work "46.4 % (13/13 own, 0/15 reassigned)"; and the fraction. */
export function progressText(u: Pick<FlightUav, 'waypoints' | 'missions' | 'progress'>): { text: string; fraction: number } {
  const w = uavWork(u);
  if (w.extra === 0) {
    const p = Math.max(0, Math.min(1, u.progress ?? (w.own ? w.ownReached / w.own : 0)));
    return { text: `${(100 * p).toFixed(1)} %${w.own ? ` (${w.ownReached}/${w.own})` : ''}`, fraction: p };
  }
  const all = w.own + w.extra;
  const p = (w.ownReached + w.extraReached) / all;
  return { text: `${(100 * p).toFixed(1)} % (${w.ownReached}/${w.own} own, ${w.extraReached}/${w.extra} reassigned)`, fraction: p };
}

/**
 * A UAV card's waypoint retries: "none" before any; "waypoint 7: 1 of 2 (3 in all)" while a waypoint is
 * being retried (`limit`: the flight's waypoint_retries, when known), state "retrying"; "3 in all" after.
 */
export function retriesText(r: FlightUav['retries'], limit?: number): { text: string; state: string } {
  const total = r?.total ?? 0;
  const count = r?.count ?? 0;
  if (r?.waypoint !== null && r?.waypoint !== undefined && count > 0)
    return { text: `waypoint ${r.waypoint}: ${count}${limit ? ` of ${limit}` : ''} (${Math.max(total, count)} in all)`, state: 'retrying' };
  if (total === 0) return { text: 'none', state: 'ok' };
  return { text: `${total} in all`, state: 'ok' };
}

/**
 * The flight's end in words: a flight `done` while a UAV's link is lost (or its link-lost alert still
 * active, or it failed) did not end well — "done with a lost UAV: B (last seen at 50 m)".
 */
export function flightOutcome(f: Pick<Flight, 'state' | 'uavs' | 'alerts'>): { outcome: string; text: string; lost: string[] } {
  const lost = new Set<string>();
  for (const u of f.uavs ?? []) if (u.link?.state === 'lost' || u.phase === 'failed') lost.add(u.uav);
  for (const a of f.alerts ?? []) if (a.active && a.kind === 'link_lost' && a.uav) lost.add(a.uav);
  const names = [...lost];
  if (f.state !== 'done' && f.state !== 'aborted') return { outcome: f.state, text: f.state, lost: names };
  if (names.length === 0) return { outcome: f.state, text: f.state, lost: names };
  const seen = names.map((id) => {
    const u = f.uavs.find((x) => x.uav === id);
    const alt = u?.position?.alt_m;
    return `${id}${typeof alt === 'number' ? ` (last seen at ${alt.toFixed(0)} m)` : ''}`;
  });
  return {
    outcome: `${f.state}-lost`,
    text: `${f.state} with ${names.length === 1 ? 'a lost UAV' : `${names.length} lost UAVs`}: ${seen.join(', ')}`,
    lost: names,
  };
}

// ---------------------------------------------------------------- photos (docs/photos.md)

/** bytes of each file sent: EXIF (with its thumbnail) and DJI's XMP lie well within it */
export const HEAD_BYTES = 256 * 1024;
/** a batch stays under the server's default body limit (10 MiB) and its 200 parts */
export const BATCH_BYTES = 8 * 1024 * 1024;
export const BATCH_PARTS = 200;

/** the files in batches of at most BATCH_PARTS heads and BATCH_BYTES bytes (pure; unit-tested) */
export function photoBatches(sizes: number[], head = HEAD_BYTES, maxBytes = BATCH_BYTES, maxParts = BATCH_PARTS): number[][] {
  const out: number[][] = [];
  let cur: number[] = [];
  let bytes = 0;
  sizes.forEach((size, i) => {
    const b = Math.min(size, head);
    if (cur.length > 0 && (cur.length >= maxParts || bytes + b > maxBytes)) {
      out.push(cur);
      cur = [];
      bytes = 0;
    }
    cur.push(i);
    bytes += b;
  });
  if (cur.length) out.push(cur);
  return out;
}

