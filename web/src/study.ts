// The study: total time and cost against the UAV count (POST /missions/{id}/studies), its chart
// (study.png) and its recommendation (study.json).
import { api, API } from './api.ts';
import type { Job } from './events.ts';
import { el, JobView } from './job-ui.ts';

export function studyPanel(getMission: () => number | null): HTMLElement {
  const wrap = el('div', { class: 'plan-study' });
  const row = el('div', { class: 'plan-row' });
  const label = el('label', {}, 'UAV counts ');
  const counts = el('input', { type: 'text', value: '1..6', size: '8', 'data-testid': 'study-uavs', 'aria-label': 'UAV counts, e.g. 1..6 or 1,2,4' });
  label.append(counts);
  const start = el('button', { type: 'button', 'data-testid': 'study-start' }, 'Study');
  row.append(label, start);
  const view = new JobView('study');
  const out = el('div', { class: 'plan-study-result', 'data-testid': 'study-result' });
  wrap.append(row, view.el, out);
  start.addEventListener('click', async () => {
    const id = getMission();
    if (id === null) return;
    start.disabled = true;
    out.replaceChildren();
    const job = await view.run(() => api.post<Job>(`/missions/${id}/studies`, { uavs: counts.value.trim() }));
    start.disabled = false;
    if (!job || job.state !== 'done') return;
    const r = job.result as { recommended_uavs?: number; min_uavs_single_battery?: number | null };
    const rec = el('p', { 'data-testid': 'study-recommendation' });
    rec.append(
      el('strong', {}, typeof r.recommended_uavs === 'number' ? `Recommended: ${r.recommended_uavs} UAV${r.recommended_uavs === 1 ? '' : 's'}` : 'No recommendation'),
    );
    if (r.min_uavs_single_battery !== undefined)
      rec.append(
        document.createTextNode(
          r.min_uavs_single_battery === null
            ? ' — no count in the range flies on a single battery'
            : ` — ${r.min_uavs_single_battery} or more fly on a single battery each`,
        ),
      );
    const img = el('img', { src: `${API}/studies/${job.id}/study.png`, alt: 'Total time and cost against the number of UAVs', class: 'plan-figure', 'data-testid': 'study-chart' });
    out.append(rec, img);
  });
  return wrap;
}
