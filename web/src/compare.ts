// Compare planners: the comparison job's table (POST /missions/{id}/comparisons) and, side by side on
// synchronised maps, one plan per planner (POST /missions/{id}/plans {planner}).
import L from 'leaflet';
import { api, API, ApiError } from './api.ts';
import type { Job } from './events.ts';
import { el, errorText, JobView } from './job-ui.ts';
import { tileUrl } from './map.ts';
import { drawPlan } from './plan-layers.ts';
import { dropPlan, loadPlan, type PreparedPlan } from './plan-source.ts';

interface Planner {
  name: string;
  summary?: string;
}

const COLUMNS: { key: string; label: string; fmt: (v: number) => string }[] = [
  { key: 'poc', label: 'PoC', fmt: (v) => `${(100 * v).toFixed(2)} %` },
  { key: 'pooc', label: 'PoOC', fmt: (v) => `${(100 * v).toFixed(2)} %` },
  { key: 'turns', label: 'Turns', fmt: (v) => v.toFixed(0) },
  { key: 'length_m', label: 'Length (m)', fmt: (v) => v.toFixed(0) },
  { key: 'flight_time_min', label: 'Flight (min)', fmt: (v) => v.toFixed(1) },
  { key: 'cost_eur', label: 'Cost (€)', fmt: (v) => v.toFixed(2) },
  { key: 'compute_time_s', label: 'Compute (s)', fmt: (v) => v.toFixed(2) },
];

export function compareTable(rows: Record<string, unknown>[]): HTMLElement {
  const table = el('table', { class: 'plan-compare-table', 'data-testid': 'compare-table' });
  const head = el('tr');
  head.append(el('th', {}, 'Planner'));
  for (const c of COLUMNS) head.append(el('th', {}, c.label));
  table.append(el('thead'), el('tbody'));
  table.tHead!.append(head);
  for (const r of rows) {
    const name = String(r.planner ?? r.name ?? '?');
    const tr = el('tr', { 'data-planner': name });
    tr.append(el('th', { scope: 'row' }, name));
    for (const c of COLUMNS) {
      const v = r[c.key];
      tr.append(el('td', { 'data-metric': c.key }, typeof v === 'number' ? c.fmt(v) : v === undefined || v === null ? '—' : String(v)));
    }
    if (typeof r.error === 'string' || (r.error && typeof r.error === 'object')) tr.title = JSON.stringify(r.error);
    table.tBodies[0].append(tr);
  }
  return table;
}

/** N small maps whose pan and zoom follow each other, each with one plan. */
function sideBySide(plans: { planner: string; prepared: PreparedPlan }[]): void {
  const overlay = el('div', { class: 'plan-overlay', 'data-testid': 'compare-maps', role: 'dialog', 'aria-label': 'Plans side by side' });
  const bar = el('div', { class: 'plan-overlay-bar' });
  const close = el('button', { type: 'button', 'data-testid': 'compare-close' }, 'Close');
  bar.append(el('strong', {}, 'Plans side by side (pan and zoom are synchronised)'), close);
  const grid = el('div', { class: 'plan-overlay-grid' });
  overlay.append(bar, grid);
  document.body.append(overlay);
  const maps: L.Map[] = [];
  const url = tileUrl(window.location.search);
  let syncing = false;
  let bounds: L.LatLngBounds | null = null;
  for (const p of plans) {
    const cell = el('div', { class: 'plan-overlay-cell' });
    const title = el('div', { class: 'plan-overlay-title' }, p.planner);
    const mapEl = el('div', { class: 'plan-overlay-map', 'data-planner': p.planner });
    cell.append(title, mapEl);
    grid.append(cell);
    const m = L.map(mapEl, { preferCanvas: true, zoomSnap: 0.25 }).setView([0, 0], 2);
    if (url) L.tileLayer(url, { maxZoom: 20, attribution: '&copy; OpenStreetMap contributors' }).addTo(m);
    L.control.scale({ imperial: false }).addTo(m);
    const d = drawPlan(m, p.prepared);
    if (d.bounds) bounds = bounds ? bounds.extend(d.bounds) : L.latLngBounds(d.bounds.getSouthWest(), d.bounds.getNorthEast());
    maps.push(m);
  }
  for (const m of maps) {
    if (bounds) m.fitBounds(bounds, { padding: [10, 10], animate: false });
    m.on('move zoom', () => {
      if (syncing) return;
      syncing = true;
      for (const o of maps) if (o !== m) o.setView(m.getCenter(), m.getZoom(), { animate: false });
      syncing = false;
    });
  }
  const dispose = () => {
    for (const m of maps) m.remove();
    overlay.remove();
    document.removeEventListener('keydown', onKey);
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
