// The plan's metrics: PoC, PoOC, turns, length, flight time, batteries, total time and cost, per UAV
// and in total, as the server computed them (GET /plans/{id} metrics and result.uavs, plan.json's
// coverage and cost blocks). Nothing is recomputed here.
import type { Job } from './events.ts';
import { el } from './job-ui.ts';
import { uavColour } from './palette.ts';
import type { PlanJson } from './plan-layers.ts';

export interface MetricRow {
  name: string;
  label: string;
  title: string;
  format: (v: number) => string;
}

const pct = (v: number) => (100 * v).toFixed(2);
const km = (v: number) => (v / 1000).toFixed(2);
const minutes = (v: number) => v.toFixed(1);
const int = (v: number) => v.toFixed(0);
const euros = (v: number) => v.toFixed(2);

export const METRICS: MetricRow[] = [
  { name: 'poc', label: 'PoC %', title: 'probability of coverage: the share of the area seen (per UAV: of the whole area)', format: pct },
  { name: 'pooc', label: 'PoOC %', title: 'probability of over-coverage: the share seen more than once', format: pct },
  { name: 'turns', label: 'Turns', title: 'turns along the path', format: int },
  { name: 'length_m', label: 'Length km', title: 'path length', format: km },
  { name: 'flight_time_min', label: 'Flight min', title: 'flight time (the mission: the longest UAV flight)', format: minutes },
  { name: 'batteries', label: 'Batteries', title: 'batteries used (total: per UAV)', format: int },
  { name: 'total_time_min', label: 'Total min', title: 'total time: deployment, flights and battery changes', format: minutes },
  { name: 'cost_eur', label: 'Cost €', title: 'flight cost', format: euros },
];

/** A structure scan's rows (issue 30): the wall's coverage, all UAVs (job.metrics facade_poc, facade_3plus). */
export const FACADE_METRICS: MetricRow[] = [
  { name: 'facade_poc', label: 'Wall seen %', title: 'the share of the wall (and roof) seen by at least one photo', format: pct },
  { name: 'facade_3plus', label: 'Wall 3+ views %', title: 'the share of the wall seen by three photos or more (what photogrammetry wants)', format: pct },
];

interface ResultUav {
  id: string;
  turns?: number;
  length_m?: number;
  share_actual?: number;
}

/** The values of each column: per UAV (in plan order), then the total. */
export function metricValues(job: Job, plan: PlanJson | null): { id: string; values: Record<string, number | undefined> }[] {
  const uavs = ((job.result.uavs as ResultUav[] | undefined) ?? []).map((u, i) => {
    const cov = plan?.coverage?.uavs?.find((c) => c.id === u.id);
    const cost = plan?.cost?.uavs?.[i];
    return {
      id: u.id,
      values: {
        poc: cov?.poc,
        pooc: cov?.pooc,
        turns: u.turns,
        length_m: u.length_m,
        flight_time_min: cost?.flight_duration_min,
        batteries: cost?.batteries,
        total_time_min: undefined,
        cost_eur: undefined,
      } as Record<string, number | undefined>,
    };
  });
  const m = job.metrics ?? {};
  const total: Record<string, number | undefined> = {};
  for (const r of [...FACADE_METRICS, ...METRICS]) total[r.name] = typeof m[r.name] === 'number' ? m[r.name] : undefined;
  total.batteries = plan?.cost?.batteries_per_uav;
  return [...uavs, { id: 'total', values: total }];
}

/** The metrics table (rows: metrics; columns: UAVs and the total). */
export function metricsPanel(job: Job, plan: PlanJson | null): HTMLElement {
  const cols = metricValues(job, plan);
  const wrap = el('div', { class: 'plan-metrics', 'data-testid': 'metrics-panel', 'data-plan-id': String(job.id) });
  const table = el('table');
  const head = el('tr');
  head.append(el('th', {}, ''));
  cols.forEach((c, i) => {
    const th = el('th', { 'data-uav': c.id });
    if (c.id !== 'total') {
      const sw = el('span', { class: 'plan-swatch' });
      sw.style.background = uavColour(i);
      th.append(sw, document.createTextNode(c.id));
    } else th.textContent = 'Total';
    head.append(th);
  });
  table.append(el('thead'), el('tbody'));
  table.tHead!.append(head);
  // a structure scan: the wall's coverage first, and the PoC named for what it is (the ground's)
  const structure = typeof job.metrics?.facade_poc === 'number';
  for (const r of structure ? [...FACADE_METRICS, ...METRICS] : METRICS) {
    const tr = el('tr');
    const label = structure && r.name === 'poc' ? 'Ground PoC %' : r.label;
    tr.append(el('th', { scope: 'row', title: r.title }, label));
    for (const c of cols) {
      const v = c.values[r.name];
      const attrs: Record<string, string> = { 'data-uav': c.id, 'data-metric': r.name };
      if (c.id === 'total') attrs['data-testid'] = `metric-${r.name}`;
      if (v !== undefined) attrs['data-value'] = String(v);
      tr.append(el('td', attrs, v === undefined ? '—' : r.format(v)));
    }
    table.tBodies[0].append(tr);
  }
  wrap.append(table);
  if (plan?.images) wrap.append(imagesPanel(plan.images));
  if (plan?.cost?.uavs === undefined)
    wrap.append(el('p', { class: 'muted' }, 'Flight time and batteries per UAV: not in plan.json.'));
  return wrap;
}

/** The photogrammetry estimate of plan.json's "images" block: images, storage, overlaps achieved, GSD. */
function imagesPanel(images: NonNullable<PlanJson['images']>): HTMLElement {
  const box = el('div', { class: 'plan-images', 'data-testid': 'images-panel' });
  const gb = images.storage_mb / 1024;
  const facts: [string, string, string][] = [
    ['images', `${images.images}`, 'expected images, all UAVs'],
    ['storage', gb >= 1 ? `${gb.toFixed(1)} GB` : `${images.storage_mb.toFixed(0)} MB`, 'storage at the camera block\'s image size'],
    ['trigger', `every ${images.trigger_distance_m.toFixed(1)} m`, `${images.capture} capture along each coverage leg`],
    ['overlap', `${(100 * images.side_overlap).toFixed(0)} % side, ${(100 * images.front_overlap).toFixed(0)} % front`, 'overlaps achieved'],
    ['gsd', images.gsd_m === null ? '—' : `${(100 * images.gsd_m).toFixed(2)} cm/px`, 'ground sample distance'],
    ['gimbal', `${images.gimbal_pitch_deg}°`, 'gimbal pitch'],
  ];
  const dl = el('dl');
  for (const [key, value, title] of facts) {
    dl.append(el('dt', { title }, key), el('dd', { 'data-testid': `images-${key}`, title }, value));
  }
  box.append(el('h4', {}, 'Images'), dl);
  const per = images.uavs.map((u) => `${u.id}: ${u.images} (every ${u.trigger_interval_s.toFixed(1)} s)`).join(' · ');
  box.append(el('p', { class: 'muted' }, per));
  return box;
}
