// The Plan tab (issue 11): plan the open mission with a live progress bar and a cancel button, draw
// each UAV's region and path on the map, the metrics panel, the coverage heatmap overlay, exports,
// the UAV-count study and the planner comparison.
import L from 'leaflet';
import { api, API, ApiError } from '../api.ts';
import { comparePanel } from '../compare.ts';
import type { Job } from '../events.ts';
import { exportsPanel } from '../exports.ts';
import { el, errorText, JobView } from '../job-ui.ts';
import { facadePanel, type FacadeJson } from '../facade-view.ts';
import { metricsPanel } from '../metrics.ts';
import { profilePanel } from '../profile.ts';
import { trajectoryPanel } from '../trajectory-view.ts';
import { latestDone, planLabel, type PlanSummary } from '../plan-history.ts';
import { fieldLayer, planFences } from '../plan-field.ts';
import { drawPlan, type DrawnPlan } from '../plan-layers.ts';
import { dropPlan, loadPlan, type PreparedPlan } from '../plan-source.ts';
import type { App, Tab } from '../state.ts';
import { studyPanel } from '../study.ts';
import { groupWarnings } from '../warnings.ts';
import { zoneLegendHtml } from '../zones.ts';
import { editableDoc } from '../mission-doc.ts';

interface Planner {
  name: string;
}

let drawn: DrawnPlan | null = null;
let heat: L.ImageOverlay | null = null;
let fieldGroup: L.LayerGroup | null = null; // rally points and geofences (issue 31)
let visible = false;
let lastPlan: { job: Job; prepared: PreparedPlan } | null = null;

function section(title: string, open = true, testid?: string): { box: HTMLDetailsElement; body: HTMLElement } {
  const box = el('details', { class: 'plan-section' });
  if (testid) box.dataset.testid = testid;
  box.open = open;
  box.append(el('summary', {}, title));
  const body = el('div', { class: 'plan-section-body' });
  box.append(body);
  return { box, body };
}

export const planTab: Tab = {
  name: 'plan',
  title: 'Plan',
  mount(panel: HTMLElement, app: App) {
    const missionId = () => app.state.missionId;
    panel.classList.add('plan-panel');
    const none = el('p', { class: 'muted', 'data-testid': 'plan-no-mission' }, 'Open or save a mission first (Missions or Define tab).');
    const body = el('div', { class: 'plan-body' });
    panel.append(none, body);

    // --- header and run controls
    const title = el('div', { class: 'plan-title', 'data-testid': 'plan-mission' });
    const controls = el('div', { class: 'plan-row' });
    const plannerSel = el('select', { 'data-testid': 'plan-planner', 'aria-label': 'Planner' });
    plannerSel.append(el('option', { value: '' }, "mission's planner"));
    const seed = el('input', { type: 'number', min: '0', step: '1', placeholder: 'seed', 'data-testid': 'plan-seed', 'aria-label': 'Seed', class: 'plan-seed' });
    const start = el('button', { type: 'button', class: 'plan-primary', 'data-testid': 'plan-start' }, 'Plan');
    controls.append(plannerSel, seed, start);
    const view = new JobView('plan');
    // the plan's warnings, grouped and rounded, below the results (issue 29, defect 6)
    const warnBox = el('details', { class: 'plan-section plan-warn-section', 'data-testid': 'plan-warnings-section', hidden: '' });
    const warnTitle = el('summary', {}, 'Warnings');
    const warnings = el('ul', { class: 'plan-warnings', 'data-testid': 'plan-warnings' });
    warnBox.append(warnTitle, warnings);
    // errors reading plans stay at the top, where the operator looks after pressing Plan
    const planErrors = el('ul', { class: 'plan-warnings', 'data-testid': 'plan-errors' });
    const stale = el('p', { class: 'plan-note', 'data-testid': 'plan-stale', hidden: '' });
    // the mission's earlier plans: the latest done one is shown when the mission is opened
    const historyRow = el('label', { class: 'plan-row plan-history', hidden: '' });
    const historySel = el('select', { 'data-testid': 'plan-history', 'aria-label': 'Plans of this mission' });
    historyRow.append(el('span', { class: 'muted' }, 'Plans:'), historySel);
    body.append(title, controls, historyRow, view.el, stale, planErrors);

    // --- results
    const legend = el('div', { class: 'plan-legend', 'data-testid': 'plan-legend' });
    const heatRow = el('label', { class: 'plan-check' });
    const heatToggle = el('input', { type: 'checkbox', 'data-testid': 'heatmap-toggle', disabled: '' });
    const heatNote = el('span', { class: 'muted' });
    heatRow.append(heatToggle, document.createTextNode(' Coverage heatmap '), heatNote);
    const fenceRow = el('label', { class: 'plan-check', title: 'each UAV’s geofence as the .plan export and the upload send it: the inclusion polygon around everything it flies (the no-fly zones are its exclusions)' });
    const fenceToggle = el('input', { type: 'checkbox', 'data-testid': 'fence-toggle' });
    const fenceNote = el('span', { class: 'muted', 'data-testid': 'fence-note' });
    fenceRow.append(fenceToggle, document.createTextNode(' Geofence '), fenceNote);
    const metricsBox = section('Metrics', true, 'metrics-section');
    const exportsBox = section('Exports', true, 'exports-section');
    // the ground under each UAV's flight, for plans that follow a DEM (issue 31)
    const profileBox = section('Ground profile', true, 'profile-section');
    // each UAV's trajectory against time, by either method (issue 33), made when the section is opened
    const trajectoryBox = section('Trajectory', false, 'trajectory-section');
    const results = el('div', { class: 'plan-results', hidden: '' });
    results.append(legend, heatRow, fenceRow, metricsBox.box, profileBox.box, trajectoryBox.box, exportsBox.box);
    const study = section('Study: how many UAVs?', false, 'study-section');
    study.body.append(studyPanel(missionId));
    const compare = section('Compare planners', false, 'compare-section');
    compare.body.append(comparePanel(missionId));
    body.append(results, warnBox, study.box, compare.box);

    api.get<{ items: Planner[] }>('/planners').then(
      (r) => {
        for (const p of r.items) plannerSel.append(el('option', { value: p.name }, p.name));
      },
      () => {
        /* the comparison panel reports it */
      },
    );

    const clear = () => {
      drawn?.remove();
      drawn = null;
      fieldGroup?.remove();
      fieldGroup = null;
      fenceNote.textContent = '';
      heat?.remove();
      heat = null;
      heatToggle.checked = false;
      heatToggle.disabled = true;
      results.hidden = true;
      if (lastPlan) dropPlan(lastPlan.prepared);
      lastPlan = null;
      warnings.replaceChildren();
      planErrors.replaceChildren();
      warnBox.hidden = true;
    };

    const showHeatmap = () => {
      heat?.remove();
      heat = null;
      if (!heatToggle.checked || !lastPlan || !visible) return;
      const b = lastPlan.job.result.heatmap_bounds as [[number, number], [number, number]] | undefined;
      if (!b) return;
      heat = L.imageOverlay(`${API}/plans/${lastPlan.job.id}/images/heatmap-overlay.png`, b, {
        opacity: 0.75,
        className: 'plan-heatmap',
        interactive: false,
      }).addTo(app.map);
    };
    heatToggle.addEventListener('change', showHeatmap);

    // the rally points (the mission's, or those the planner proposed) and, when asked, the geofences
    const showField = async () => {
      fieldGroup?.remove();
      fieldGroup = null;
      if (!lastPlan || !visible) return;
      const shown = lastPlan;
      const plan = shown.prepared.plan;
      const rally = Array.isArray(plan.rally) ? (plan.rally as [number, number][]) : [];
      let fences = null;
      if (fenceToggle.checked) {
        fenceNote.textContent = '(loading…)';
        fences = await planFences(shown.job.id, plan.uavs.map((u) => u.id));
        if (lastPlan !== shown || !visible) return;
        const n = fences.reduce((s, f) => s + f.polygons.length, 0);
        fenceNote.textContent = `(${n} inclusion polygon${n === 1 ? '' : 's'}; the no-fly zones are its exclusions)`;
        fenceNote.dataset.polygons = String(n);
      } else {
        fenceNote.textContent = '';
      }
      (fieldGroup as L.LayerGroup | null)?.remove(); // another call may have drawn meanwhile
      fieldGroup = fieldLayer(rally, fences).addTo(app.map);
    };
    fenceToggle.addEventListener('change', () => void showField());

    const render = (job: Job, prepared: PreparedPlan) => {
      clear();
      lastPlan = { job, prepared };
      const plan = prepared.plan;
      const { summary } = prepared;
      if (visible) {
        // the plan's view first, without animation: the tiles are drawn once, for that view
        if (summary.bounds) app.map.fitBounds(summary.bounds, { padding: [20, 20], animate: false });
        drawn = drawPlan(app.map, prepared);
        void showField();
      }
      legend.replaceChildren();
      for (const c of summary.uavs) {
        const id = c.id;
        const item = el('div', { class: 'plan-legend-item', 'data-testid': 'plan-legend-item', 'data-uav': id, 'data-regions': String(c.polygons), 'data-paths': String(c.paths) });
        const sw = el('span', { class: 'plan-swatch' });
        sw.style.background = c.colour;
        item.append(sw, document.createTextNode(`${id}: ${c.polygons} region polygon${c.polygons === 1 ? '' : 's'}, ${c.paths} path part${c.paths === 1 ? '' : 's'}, ${c.waypoints} waypoints`));
        legend.append(item);
      }
      legend.append(el('div', { class: 'muted plan-legend-key' }, 'solid: coverage · dashed: transit · ● start · ○ return · numbers from zoom 17'));
      const zoneKey = el('div', { class: 'zone-legend', 'data-testid': 'plan-zone-legend' });
      zoneKey.innerHTML = zoneLegendHtml();
      legend.append(zoneKey);
      const hasHeat = Array.isArray(job.result.heatmap_bounds);
      heatToggle.disabled = !hasHeat;
      heatNote.textContent = hasHeat ? '' : '(this plan has no heatmap overlay)';
      const groups = groupWarnings(job.warnings ?? []);
      for (const g of groups) {
        const li = el('li', { 'data-testid': 'plan-warning', 'data-count': String(g.count) }, g.text);
        if (g.count > 1) li.append(el('span', { class: 'plan-warn-count' }, ` ×${g.count}`));
        li.title = g.raw.join('\n');
        warnings.append(li);
      }
      const total = (job.warnings ?? []).length;
      warnTitle.textContent = `Warnings: ${groups.length}${total > groups.length ? ` distinct of ${total}` : ''}`;
      warnBox.hidden = groups.length === 0;
      warnBox.open = groups.length <= 3;
      metricsBox.body.replaceChildren(metricsPanel(job, plan));
      // a structure scan: its wall unrolled, coloured by the photos that see it
      if (plan?.facade) metricsBox.body.append(facadePanel(plan.facade as FacadeJson));
      exportsBox.body.replaceChildren(exportsPanel(job.id, plan.uavs.map((u) => u.id)));
      const terrain = (plan.mission as Record<string, unknown> | undefined)?.terrain;
      profileBox.box.hidden = !terrain;
      profileBox.body.replaceChildren();
      if (terrain) profileBox.body.append(profilePanel(job.id, summary.uavs.filter((c) => c.paths > 0).map((c) => c.id)));
      trajectoryBox.body.replaceChildren();
      const flying = summary.uavs.filter((c) => c.paths > 0).map((c) => c.id);
      const openTrajectory = () => {
        if (trajectoryBox.box.open && trajectoryBox.body.childElementCount === 0)
          trajectoryBox.body.append(trajectoryPanel(job.id, flying));
      };
      trajectoryBox.box.ontoggle = openTrajectory;
      openTrajectory();
      results.hidden = false;
    };

    const load = async (job: Job) => {
      const seq = ++loadSeq;
      try {
        const prepared = await loadPlan(job.id);
        if (seq !== loadSeq || job.mission_id !== app.state.missionId) {
          dropPlan(prepared);
          return; // another plan or mission since
        }
        render(job, prepared);
        historySel.value = String(job.id);
        app.update({ planId: job.id });
      } catch (e) {
        const s = el('li', { class: 'plan-error' }, `The plan's files cannot be read: ${errorText(e as ApiError)}`);
        planErrors.append(s);
      }
    };

    let loadSeq = 0;
    let historySeq = 0;
    let history: PlanSummary[] = [];
    /** Lists the mission's plans; `openLatest`: show the newest done one unless a plan of it is shown. */
    const refreshHistory = async (openLatest: boolean) => {
      const id = missionId();
      const seq = ++historySeq;
      if (id === null) {
        history = [];
        historySel.replaceChildren();
        historyRow.hidden = true;
        return;
      }
      let items: PlanSummary[];
      try {
        items = (await api.get<{ items: PlanSummary[] }>(`/missions/${id}/plans?limit=20`)).items;
      } catch (e) {
        if (seq !== historySeq) return;
        planErrors.append(el('li', { class: 'plan-error' }, `The mission's plans cannot be listed: ${errorText(e as ApiError)}`));
        return;
      }
      if (seq !== historySeq || id !== missionId()) return;
      history = items;
      historySel.replaceChildren();
      historySel.append(el('option', { value: '' }, items.length ? `${items.length === 20 ? 'latest 20' : items.length} plan${items.length === 1 ? '' : 's'} of this mission` : 'no plans yet'));
      for (const p of items) {
        const o = el('option', { value: String(p.id), 'data-state': p.state }, planLabel(p));
        if (p.state !== 'done') o.disabled = true;
        historySel.append(o);
      }
      historyRow.hidden = items.length === 0;
      const shown = lastPlan?.job.mission_id === id ? lastPlan.job.id : null;
      historySel.value = shown !== null && items.some((p) => p.id === shown) ? String(shown) : '';
      if (openLatest && shown === null && !view.busy) {
        const latest = latestDone(items);
        if (latest) await openPlan(latest.id);
      }
    };
    const openPlan = async (planId: number) => {
      try {
        const job = await api.get<Job>(`/plans/${planId}`);
        if (job.mission_id !== missionId()) return;
        await load(job);
      } catch (e) {
        planErrors.append(el('li', { class: 'plan-error' }, `Plan #${planId} cannot be opened: ${errorText(e as ApiError)}`));
      }
    };
    historySel.addEventListener('change', () => {
      const planId = Number(historySel.value);
      if (planId > 0 && planId !== lastPlan?.job.id && history.some((p) => p.id === planId && p.state === 'done')) void openPlan(planId);
    });

    start.addEventListener('click', async () => {
      const id = missionId();
      if (id === null) return;
      const req: Record<string, unknown> = {};
      if (plannerSel.value) req.planner = plannerSel.value;
      if (seed.value.trim() !== '') req.seed = Number(seed.value);
      start.disabled = true;
      clear();
      const job = await view.run(() => api.post<Job>(`/missions/${id}/plans`, req));
      start.disabled = false;
      if (job?.state === 'done') await load(job);
      updateHeader();
      void refreshHistory(false);
    });

    const updateHeader = () => {
      const s = app.state;
      none.hidden = s.missionId !== null;
      body.hidden = s.missionId === null;
      const name = (s.mission?.name as string | undefined) ?? '';
      title.textContent = s.missionId === null ? '' : `Mission #${s.missionId}${name ? ` — ${name}` : ''}, revision ${s.revision ?? '?'}`;
      const planned = lastPlan?.job;
      if (planned && (planned.mission_id !== s.missionId || planned.revision !== s.revision)) {
        stale.hidden = false;
        stale.textContent = `This plan is of mission #${planned.mission_id} revision ${planned.revision}; plan again to follow the changes.`;
      } else stale.hidden = true;
    };
    let lastMission: number | null = null;
    app.subscribe((s) => {
      if (s.missionId !== lastMission) {
        lastMission = s.missionId;
        if (lastPlan && lastPlan.job.mission_id !== s.missionId) clear();
        void refreshHistory(true);
      }
      updateHeader();
    });
    updateHeader();

    // a link to a mission: ?mission=ID opens it here when nothing else is open
    const linked = Number(new URLSearchParams(window.location.search).get('mission'));
    if (Number.isInteger(linked) && linked > 0)
      api.get<{ id: number; revision: number; mission: Record<string, unknown>; source?: unknown }>(`/missions/${linked}`).then(
        (m) => {
          if (app.state.missionId === null) app.update({ missionId: m.id, revision: m.revision, mission: editableDoc(m), dirty: false });
        },
        (e: ApiError) => {
          none.className = 'plan-error';
          none.textContent = `Mission #${linked} cannot be opened: ${errorText(e)}`;
        },
      );

    this.show = () => {
      visible = true;
      updateHeader();
      if (lastPlan && !drawn) {
        drawn = drawPlan(app.map, lastPlan.prepared);
        showHeatmap();
        void showField();
      }
    };
    this.hide = () => {
      visible = false;
      drawn?.remove();
      drawn = null;
      heat?.remove();
      heat = null;
      fieldGroup?.remove();
      fieldGroup = null;
    };
  },
};
