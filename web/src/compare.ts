// Compare planners: the comparison job's table (POST /missions/{id}/comparisons) and, side by side on
// synchronised maps, one plan per planner (POST /missions/{id}/plans {planner}).
import L from 'leaflet';
import { api, API, ApiError } from './api.ts';
import type { Job } from './events.ts';
import { el, errorText, JobView } from './job-ui.ts';
import { baseTileLayer } from './map.ts';
import { drawPlan } from './plan-layers.ts';
import { dropPlan, loadPlan, type PreparedPlan } from './plan-source.ts';

interface Planner {
  name: string;
  summary?: string;
}

const ROWS: { key: string; label: string; title: string; fmt: (v: number) => string }[] = [
  { key: 'poc', label: 'PoC', title: 'probability of coverage', fmt: (v) => `${(100 * v).toFixed(2)} %` },
  { key: 'pooc', label: 'PoOC', title: 'probability of over-coverage', fmt: (v) => `${(100 * v).toFixed(2)} %` },
  { key: 'turns', label: 'Turns', title: 'turns of all UAVs', fmt: (v) => Math.round(v).toLocaleString('en-GB') },
  { key: 'length_m', label: 'Length', title: 'path length of all UAVs', fmt: (v) => (v >= 10000 ? `${(v / 1000).toFixed(1)} km` : `${Math.round(v)} m`) },
  { key: 'flight_time_min', label: 'Flight time', title: 'flight time of the longest UAV', fmt: (v) => `${v.toFixed(1)} min` },
  { key: 'batteries_per_uav', label: 'Batteries', title: 'batteries per UAV', fmt: (v) => v.toFixed(0) },
  { key: 'cost_eur', label: 'Cost', title: 'flight cost', fmt: (v) => `${v.toFixed(2)} €` },
  { key: 'compute_time_s', label: 'Compute', title: 'planning time', fmt: (v) => `${v.toFixed(2)} s` },
];

/** A long name with soft hyphens every 7 letters, so that a narrow column breaks it with a hyphen ("boustro-phedon"). */
const breakable = (name: string): string => (name.length > 10 ? name.replace(/([a-z]{7})(?=[a-z]{4})/g, '$1\u00ad') : name);
const rowName = (r: Record<string, unknown>): string => String(r.planner ?? r.name ?? '?');
const numberOf = (r: Record<string, unknown>, k: string): number | null => (typeof r[k] === 'number' && Number.isFinite(r[k]) ? (r[k] as number) : null);

/**
 * Words of caution for a planner that needs far more than the best one here (issue 29, defect 9):
 * "spiral: 4.2× darp's length here (117 km against 28 km), 10 331 turns, 47 batteries".
 */
export function compareCautions(rows: Record<string, unknown>[], factor = 2): { planner: string; text: string }[] {
  const withLength = rows.filter((r) => (numberOf(r, 'length_m') ?? 0) > 0);
  if (withLength.length < 2) return [];
  const best = withLength.reduce((a, b) => (numberOf(b, 'length_m')! < numberOf(a, 'length_m')! ? b : a));
  const bestLen = numberOf(best, 'length_m')!;
  const km = (m: number) => (m >= 10000 ? `${(m / 1000).toFixed(0)} km` : `${(m / 1000).toFixed(1)} km`);
  const out: { planner: string; text: string }[] = [];
  for (const r of withLength) {
    const len = numberOf(r, 'length_m')!;
    if (r === best || len < factor * bestLen) continue;
    const extra: string[] = [];
    const turns = numberOf(r, 'turns');
    const bat = numberOf(r, 'batteries_per_uav');
    if (turns !== null) extra.push(`${Math.round(turns).toLocaleString('en-GB')} turns`);
    if (bat !== null) extra.push(`${bat.toFixed(0)} batteries per UAV`);
    out.push({
      planner: rowName(r),
      text: `${rowName(r)}: ${(len / bestLen).toFixed(1)}× ${rowName(best)}'s length here (${km(len)} against ${km(bestLen)})${extra.length ? `, ${extra.join(', ')}` : ''}.`,
    });
  }
  return out;
}

/** The comparison as a table that fits the panel: one column per planner, one row per metric. */
export function compareTable(rows: Record<string, unknown>[]): HTMLElement {
  const wrap = el('div', { class: 'plan-compare-wrap' });
  const table = el('table', { class: 'plan-compare-table', 'data-testid': 'compare-table' });
  const head = el('tr');
  head.append(el('th', { scope: 'col' }, ''));
  for (const r of rows) {
    const th = el('th', { scope: 'col', 'data-planner': rowName(r), title: rowName(r) }, breakable(rowName(r)));
    if (typeof r.error === 'string' || (r.error && typeof r.error === 'object')) th.title = JSON.stringify(r.error);
    head.append(th);
  }
  table.append(el('thead'), el('tbody'));
  table.tHead!.append(head);
  // the best value per metric is marked (lowest, but highest PoC)
  for (const c of ROWS) {
    const tr = el('tr', { 'data-metric': c.key });
    tr.append(el('th', { scope: 'row', title: c.title }, c.label));
    const values = rows.map((r) => numberOf(r, c.key));
    const known = values.filter((v): v is number => v !== null);
    const best = known.length > 1 ? (c.key === 'poc' ? Math.max(...known) : Math.min(...known)) : null;
    rows.forEach((r, i) => {
      const v = r[c.key];
      const td = el('td', { 'data-metric': c.key, 'data-planner': rowName(r) }, typeof v === 'number' ? c.fmt(v) : v === undefined || v === null ? '—' : String(v));
      if (typeof v === 'number') td.dataset.value = String(v);
      if (best !== null && values[i] === best && c.key !== 'compute_time_s') td.classList.add('plan-compare-best');
      tr.append(td);
    });
    table.tBodies[0].append(tr);
  }
  wrap.append(table);
  const cautions = compareCautions(rows);
  if (cautions.length) {
    const ul = el('ul', { class: 'plan-compare-cautions', 'data-testid': 'compare-cautions' });
    for (const c of cautions) ul.append(el('li', { 'data-testid': 'compare-caution', 'data-planner': c.planner }, c.text));
    wrap.append(ul);
  }
  return wrap;
}

/**
 * N maps of the same size showing the same view, each with one plan: one zoom and centre that shows
 * every plan whole on all of them, and a pan or zoom of any map applied to the others at once (issue
 * 29, defect 2: no animation, so that every map is at the same place at every frame).
 */
function sideBySide(plans: { planner: string; prepared: PreparedPlan }[]): void {
  const overlay = el('div', { class: 'plan-overlay', 'data-testid': 'compare-maps', role: 'dialog', 'aria-label': 'Plans side by side' });
  const bar = el('div', { class: 'plan-overlay-bar' });
  const close = el('button', { type: 'button', 'data-testid': 'compare-close' }, 'Close');
  bar.append(el('strong', {}, 'Plans side by side (pan and zoom are synchronised)'), close);
  const grid = el('div', { class: 'plan-overlay-grid' });
  // equal cells: as many columns as fit three plans a row, never wider than the screen
  const cols = Math.min(plans.length, window.innerWidth < 700 ? 1 : plans.length <= 3 ? plans.length : Math.ceil(plans.length / 2));
  grid.style.gridTemplateColumns = `repeat(${cols}, minmax(0, 1fr))`;
  grid.style.gridAutoRows = 'minmax(0, 1fr)';
  overlay.append(bar, grid);
  document.body.append(overlay);
  const maps: L.Map[] = [];
  let bounds: L.LatLngBounds | null = null;
  const cells: HTMLElement[] = [];
  for (const p of plans) {
    const cell = el('div', { class: 'plan-overlay-cell' });
    const title = el('div', { class: 'plan-overlay-title' }, p.planner);
    const mapEl = el('div', { class: 'plan-overlay-map', 'data-planner': p.planner });
    cell.append(title, mapEl);
    grid.append(cell);
    cells.push(mapEl);
    const b = p.prepared.summary.bounds ? L.latLngBounds(p.prepared.summary.bounds) : null;
    if (b) bounds = bounds ? bounds.extend(b) : L.latLngBounds(b.getSouthWest(), b.getNorthEast());
  }
  // the common view, from the maps' real sizes (the overlay is laid out by now)
  void overlay.offsetWidth;
  const size = cells.reduce((s, c) => L.point(Math.min(s.x, c.clientWidth), Math.min(s.y, c.clientHeight)), L.point(Infinity, Infinity));
  for (const [i, p] of plans.entries()) {
    const m = L.map(cells[i], { preferCanvas: true, zoomSnap: 0.25, zoomAnimation: false, fadeAnimation: false, markerZoomAnimation: false, inertia: false });
    baseTileLayer()?.addTo(m);
    L.control.scale({ imperial: false }).addTo(m);
    if (bounds) {
      // the largest zoom at which the union of the plans fits the smallest map, with a margin
      const pad = L.point(20, 20);
      let z = m.getBoundsZoom(bounds, false, pad);
      if (size.x < Infinity) {
        const fit = (zoom: number) => {
          const sw = m.project(bounds!.getSouthWest(), zoom);
          const ne = m.project(bounds!.getNorthEast(), zoom);
          return Math.abs(ne.x - sw.x) <= size.x - 2 * pad.x && Math.abs(sw.y - ne.y) <= size.y - 2 * pad.y;
        };
        while (z > 0 && !fit(z)) z -= 0.25;
      }
      m.setView(bounds.getCenter(), z, { animate: false });
    } else m.setView([0, 0], 2);
    drawPlan(m, p.prepared);
    // the view on the element, for people's tools and the tests: zoom, centre, [s, w, n, e]
    const mark = () => {
      const c = m.getCenter();
      const b = m.getBounds();
      cells[i].dataset.zoom = String(m.getZoom());
      cells[i].dataset.center = `${c.lat.toFixed(6)},${c.lng.toFixed(6)}`;
      cells[i].dataset.view = [b.getSouth(), b.getWest(), b.getNorth(), b.getEast()].map((x) => x.toFixed(7)).join(',');
    };
    m.on('moveend zoomend', mark);
    mark();
    maps.push(m);
  }
  let syncing = false;
  const sync = (from: L.Map) => {
    if (syncing) return;
    syncing = true;
    const c = from.getCenter();
    const z = from.getZoom();
    for (const o of maps) if (o !== from && (o.getZoom() !== z || !o.getCenter().equals(c, 1e-9))) o.setView(c, z, { animate: false });
    syncing = false;
  };
  for (const m of maps) m.on('move zoom moveend zoomend', () => sync(m));
  const onResize = () => {
    for (const m of maps) m.invalidateSize({ animate: false });
    if (maps[0]) sync(maps[0]);
  };
  window.addEventListener('resize', onResize);
  const dispose = () => {
    for (const m of maps) m.remove();
    overlay.remove();
    document.removeEventListener('keydown', onKey);
    window.removeEventListener('resize', onResize);
  };
  const onKey = (e: KeyboardEvent) => {
    if (e.key === 'Escape') dispose();
  };
  document.addEventListener('keydown', onKey);
  close.addEventListener('click', dispose);
}

export function comparePanel(getMission: () => number | null): HTMLElement {
  const wrap = el('div', { class: 'plan-compare' });
  const list = el('div', { class: 'plan-compare-list', 'data-testid': 'compare-planners' });
  const start = el('button', { type: 'button', 'data-testid': 'compare-start' }, 'Compare');
  const side = el('button', { type: 'button', 'data-testid': 'compare-side-by-side', disabled: '' }, 'Side by side');
  const note = el('div', { class: 'plan-export-status', role: 'status', 'data-testid': 'compare-status' });
  const row = el('div', { class: 'plan-row' });
  row.append(start, side);
  const view = new JobView('compare');
  const out = el('div', { class: 'plan-compare-result' });
  wrap.append(list, row, view.el, note, out);
  let plans: { planner: string; prepared: PreparedPlan }[] = [];

  api.get<{ items: Planner[] }>('/planners').then(
    (r) => {
      r.items.forEach((p, i) => {
        const label = el('label', { class: 'plan-check', title: p.summary ?? '' });
        const cb = el('input', { type: 'checkbox', value: p.name, 'data-testid': 'compare-planner', 'data-planner': p.name });
        if (i < 2) cb.checked = true;
        label.append(cb, document.createTextNode(` ${p.name}`));
        list.append(label);
      });
    },
    (e: ApiError) => {
      list.className = 'plan-error';
      list.textContent = `The planners cannot be listed: ${errorText(e)}`;
    },
  );

  start.addEventListener('click', async () => {
    const id = getMission();
    if (id === null) return;
    const chosen = [...list.querySelectorAll<HTMLInputElement>('input:checked')].map((c) => c.value);
    note.className = 'plan-export-status';
    note.textContent = '';
    if (chosen.length < 2) {
      note.className = 'plan-export-status plan-error';
      note.textContent = 'Pick two planners or more.';
      return;
    }
    start.disabled = true;
    side.disabled = true;
    out.replaceChildren();
    for (const p of plans) dropPlan(p.prepared);
    plans = [];
    // one plan per planner for the maps, queued next to the comparison
    const planJobs = chosen.map((planner) =>
      api.post<Job>(`/missions/${id}/plans`, { planner }).then(
        (j) => ({ planner, id: j.id }),
        (e: ApiError) => ({ planner, error: errorText(e) }),
      ),
    );
    const job = await view.run(() => api.post<Job>(`/missions/${id}/comparisons`, { planners: chosen }));
    start.disabled = false;
    if (job?.state === 'done') {
      const rows = (job.result.planners as Record<string, unknown>[] | undefined) ?? [];
      out.append(compareTable(rows));
    }
    // wait for the plans (a comparison done means they are queued or running on the same workers)
    const submitted = await Promise.all(planJobs);
    const problems: string[] = [];
    for (const s of submitted) {
      if ('error' in s) {
        problems.push(`${s.planner}: ${s.error}`);
        continue;
      }
      const done = await waitDone(s.id);
      if (done.state !== 'done') {
        problems.push(`${s.planner}: ${done.state}${done.error ? ` — ${errorText(done.error)}` : ''}`);
        continue;
      }
      try {
        plans.push({ planner: s.planner, prepared: await loadPlan(s.id) });
      } catch (e) {
        problems.push(`${s.planner}: ${errorText(e as ApiError)}`);
      }
    }
    side.disabled = plans.length < 2;
    if (problems.length) {
      note.className = 'plan-export-status plan-error';
      note.textContent = `Side by side incomplete: ${problems.join('; ')}`;
    } else note.textContent = `${plans.length} plans ready side by side.`;
  });
  side.addEventListener('click', () => sideBySide(plans));
  return wrap;
}

/** Polls a plan until it ends (the comparison's own progress is what the operator watches). */
async function waitDone(id: number): Promise<Job> {
  for (;;) {
    const j = await api.get<Job>(`/plans/${id}`);
    if (j.state === 'done' || j.state === 'failed' || j.state === 'cancelled') return j;
    await new Promise((r) => setTimeout(r, 500));
  }
}

export const compareImage = (id: number): string => `${API}/comparisons/${id}/compare.png`;
