// The Fly tab (issue 12, docs/flights.md): fly the selected plan. It lists the plan's flights, starts a
// simulated fleet in one click (optionally with a failing UAV) or binds real vehicles over MAVLink
// (an endpoint per UAV, listen or connect), sends the operator's commands, and follows the flight live
// over the events WebSocket: UAVs on the map (fly-layers.ts), a card per UAV, alerts and reassignment
// offers (fly-panel.ts), the flown coverage overlay refreshed every few seconds; after the flight, a
// replay with a time slider, flown against planned PoC, and the log as CSV / GeoJSON (fly-replay.ts).
import { api, API, ApiError } from '../api.ts';
import { events, type Job } from '../events.ts';
import { FlyLayers, type UavFrame } from '../fly-layers.ts';
import { failSpec, flightEnded, flightOutcome, planWaypoints, type Flight, type FlightCoverage, type FlightUav, type UavLines } from '../fly-model.ts';
import { FlyPanel } from '../fly-panel.ts';
import { FlyPhotos } from '../fly-photos.ts';
import { FlyReplay } from '../fly-replay.ts';
import { el, errorText } from '../job-ui.ts';
import { uavColour } from '../palette.ts';
import type { PathsGeoJson } from '../plan-geometry.ts';
import type { App, Tab } from '../state.ts';
import { zoneLegendHtml, zoneRings } from '../zones.ts';
import '../fly.css';

/** Fleet-wide commands, in the order an operator needs them. */
const COMMANDS: [string, string][] = [
  ['upload', 'Upload'],
  ['start', 'Start'],
  ['pause', 'Pause'],
  ['continue', 'Continue'],
  ['rtl', 'RTL'],
  ['land', 'Land'],
  ['abort', 'Abort'],
  ['resume', 'Resume'],
  ['next_sortie', 'Next sortie'],
];

/** The flown coverage overlay and PoC are read again this often while a flight is on. */
const COVERAGE_MS = 3000;

interface PlanInfo {
  id: number;
  job: Job;
  uavs: { id: string; colour: string }[];
  lines: Map<string, UavLines>;
}

function section(title: string, open: boolean, testid: string): { box: HTMLDetailsElement; body: HTMLElement } {
  const box = el('details', { class: 'plan-section', 'data-testid': testid });
  box.open = open;
  box.append(el('summary', {}, title));
  const body = el('div', { class: 'plan-section-body' });
  box.append(body);
  return { box, body };
}

function numberInput(testid: string, value: string, attrs: Record<string, string> = {}): HTMLInputElement {
  return el('input', { type: 'number', value, 'data-testid': testid, class: 'fly-num', ...attrs });
}

function labelled(text: string, input: HTMLElement): HTMLLabelElement {
  const l = el('label', { class: 'fly-field' });
  l.append(el('span', { class: 'muted' }, text), input);
  return l;
}

const flightLabel = (f: Flight): string => {
  const when = f.created ? new Date(f.created).toLocaleTimeString() : '';
  return `#${f.id} · ${f.state}${f.simulated ? ' · simulated' : ''}${when ? ` · ${when}` : ''}`;
};

export const flyTab: Tab = {
  name: 'fly',
  title: 'Fly',
  mount(panel: HTMLElement, app: App) {
    panel.classList.add('plan-panel', 'fly-panel');
    const layers = new FlyLayers(app.map);
    let plan: PlanInfo | null = null;
    let flight: Flight | null = null;
    let unwatch: (() => void) | null = null;
    let visible = false;
    let fitted: number | null = null;
    let coverageTimer: number | null = null;
    let coverageSeq = 0;
    let autoStart: number | null = null; // a simulated flight to start once its missions are uploaded
    let planSeq = 0;
    /** the operator's last command, until the flight shows what became of it */
    let lastCommand: { command: string; reassignment?: number } | null = null;

    // --- the plan and its flights
    const none = el('p', { class: 'muted', 'data-testid': 'fly-no-plan' }, 'No plan yet: plan the mission in the Plan tab.');
    const body = el('div', { class: 'plan-body', hidden: '' });
    const title = el('div', { class: 'plan-title', 'data-testid': 'fly-plan' });
    const listRow = el('label', { class: 'plan-row' });
    const flightSel = el('select', { 'data-testid': 'fly-flights', 'aria-label': 'Flights of this plan', class: 'fly-flights' });
    listRow.append(el('span', { class: 'muted' }, 'Flights:'), flightSel);
    // the mission's flights that have not ended, of any plan (GET /missions/{id}/flights): aircraft in
    // the air stay one click away whatever plan is open (issue 29, defect 1)
    const activeBox = el('div', { class: 'fly-active', 'data-testid': 'fly-active', hidden: '', role: 'region', 'aria-label': 'Flights not ended' });
    const otherPlan = el('div', { class: 'plan-note fly-other-plan', 'data-testid': 'fly-other-plan', hidden: '' });
    panel.append(activeBox, none, body);

    // --- a new flight: simulated, or real vehicles
    const create = section('New flight', true, 'fly-new');
    const speedup = numberInput('fly-speedup', '20', { min: '1', max: '1000', step: '1', 'aria-label': 'Simulation speed-up' });
    const failUav = el('select', { 'data-testid': 'fly-fail-uav', 'aria-label': 'Failing UAV' });
    const failAt = numberInput('fly-fail-at', '40', { min: '0', max: '100', step: '1', 'aria-label': 'Failure at % of its mission' });
    const failKind = el('select', { 'data-testid': 'fly-fail-kind', 'aria-label': 'Failure kind' });
    failKind.append(
      el('option', { value: 'link' }, 'link loss'),
      el('option', { value: 'land' }, 'forced landing'),
      el('option', { value: 'stuck' }, 'stuck (no progress)'),
    );
    const simulate = el('button', { type: 'button', class: 'plan-primary', 'data-testid': 'fly-simulate' }, 'Simulate fleet');
    const simRow = el('div', { class: 'plan-row' });
    simRow.append(labelled('speed-up ×', speedup), simulate);
    const failRow = el('div', { class: 'plan-row' });
    failRow.append(labelled('failure:', failUav), labelled('at %', failAt), failKind);
    const realBox = section('Real vehicles (MAVLink 2 over UDP)', false, 'fly-bind');
    const vehicleRows = el('div', { class: 'fly-vehicles' });
    const connect = el('button', { type: 'button', 'data-testid': 'fly-connect' }, 'Connect vehicles');
    realBox.body.append(vehicleRows, connect);
    const settingsBox = section('Flight settings', false, 'fly-settings');
    const autoReassign = el('input', { type: 'checkbox', 'data-testid': 'fly-auto-reassign' });
    const separation = numberInput('fly-separation', '10', { min: '0', step: '1' });
    const deviation = numberInput('fly-deviation', '15', { min: '0', step: '1' });
    const lowBattery = numberInput('fly-low-battery', '25', { min: '0', max: '100', step: '1' });
    const linkTimeout = numberInput('fly-link-timeout', '3', { min: '0.5', step: '0.5' });
    const reassignAfter = numberInput('fly-reassign-after', '10', { min: '1', step: '1' });
    const waypointRetries = numberInput('fly-waypoint-retries', '2', { min: '0', max: '10', step: '1' });
    // where reassigned work starts (docs/flights.md, Reassignment): take-off points, or live positions
    const reassignFrom = el('select', { 'data-testid': 'fly-reassign-from' });
    reassignFrom.append(el('option', { value: 'home' }, 'home (after landing)'), el('option', { value: 'air' }, 'where they are (in the air)'));
    const autoRow = el('label', { class: 'plan-check' });
    autoRow.append(autoReassign, document.createTextNode(' apply reassignments without asking'));
    const settingsGrid = el('div', { class: 'fly-settings-grid' });
    for (const [label, input] of [
      ['separation alert below (m)', separation],
      ['off-path alert beyond (m)', deviation],
      ['low battery alert below (%)', lowBattery],
      ['link lost after (s)', linkTimeout],
      ['offer reassignment after (s)', reassignAfter],
      ['waypoint retries (0: off)', waypointRetries],
      ['helpers start from', reassignFrom],
    ] as [string, HTMLElement][]) {
      input.setAttribute('aria-label', label);
      settingsGrid.append(el('span', { class: 'muted' }, label), input);
    }
    settingsBox.body.append(autoRow, settingsGrid);
    const createMsg = el('div', { class: 'fly-message', 'data-testid': 'fly-create-message', role: 'status' });
    create.body.append(simRow, failRow, realBox.box, settingsBox.box, createMsg);

    // --- the flight
    const stateLine = el('div', { class: 'fly-state', 'data-testid': 'fly-state', role: 'status' });
    const cmdRow = el('div', { class: 'fly-cmds', 'data-testid': 'fly-commands' });
    const cmdButtons = new Map<string, HTMLButtonElement>();
    for (const [cmd, label] of COMMANDS) {
      const b = el('button', { type: 'button', 'data-testid': `fly-cmd-${cmd}`, class: cmd === 'abort' ? 'fly-danger' : '' }, label);
      b.addEventListener('click', () => void send(cmd));
      cmdButtons.set(cmd, b);
      cmdRow.append(b);
    }
    const stop = el('button', { type: 'button', 'data-testid': 'fly-stop', class: 'plan-small' }, 'Stop following');
    stop.title = 'DELETE the flight: the server stops following it (and stops its simulated fleet)';
    const cmdMsg = el('div', { class: 'fly-message', 'data-testid': 'fly-message', role: 'status' });
    stop.addEventListener('click', async () => {
      const f = flight;
      if (!f) return;
      stop.disabled = true;
      try {
        applyFlight(await api.del<Flight>(`/flights/${f.id}`));
        cmdMsg.className = 'fly-message';
        cmdMsg.textContent = 'The server no longer follows this flight.';
      } catch (e) {
        stop.disabled = false;
        cmdMsg.className = 'fly-message plan-error';
        cmdMsg.textContent = `Stop: ${errorText(e as ApiError)}`;
      }
    });
    const live = new FlyPanel(
      (cmd, extra) => void send(cmd, extra),
      (uav) => plan?.uavs.find((u) => u.id === uav)?.colour ?? '#888',
      (uav) => layers.focus(uav),
    );
    const replay = new FlyReplay(
      layers,
      () => new Map((plan?.uavs ?? []).map((u) => [u.id, plan!.lines.get(u.id)?.waypoints.length ?? 0])),
      (active) => {
        // leaving the replay: the live (or final) state again
        if (!active && flight) drawFlight(flight);
      },
    );
    const flightBox = el('div', { class: 'fly-flight', hidden: '' });
    const afterBox = section('After the flight', true, 'fly-after');
    // refly the gaps (docs/refly.md): a plan job of the mission for what the tracks did not scan
    const reflyBtn = el('button', { type: 'button', class: 'plan-small', 'data-testid': 'fly-refly' }, 'Refly the gaps');
    reflyBtn.title = 'Plan what this flight did not scan, as a new plan of the mission (POST /flights/{id}/refly)';
    const reflyMsg = el('div', { class: 'fly-message', 'data-testid': 'fly-refly-message', role: 'status' });
    reflyBtn.addEventListener('click', async () => {
      const f = flight;
      if (!f) return;
      reflyBtn.disabled = true;
      reflyMsg.className = 'fly-message';
      reflyMsg.textContent = 'Finding the gaps…';
      try {
        const job = await api.post<Job & { params?: { refly?: { gaps_m2?: number; flown_poc?: number } } }>(`/flights/${f.id}/refly`, {});
        const r = job.params?.refly;
        reflyMsg.textContent =
          `Refly plan #${job.id} queued` +
          (r ? `: ${Math.round(r.gaps_m2 ?? 0).toLocaleString('en')} m² of gaps, the flight scanned ${((r.flown_poc ?? 0) * 100).toFixed(1)} %` : '') +
          '. It opens from the Plan tab\'s plans of this mission.';
      } catch (e) {
        reflyMsg.className = 'fly-message plan-error';
        reflyMsg.textContent = `Refly: ${errorText(e as ApiError)}`;
      } finally {
        reflyBtn.disabled = false;
      }
    });
    const reflyRow = el('div', { class: 'plan-row' });
    reflyRow.append(reflyBtn);
    // what the photos saw (docs/photos.md), and the refly from them
    const photos = new FlyPhotos(app.map, () => flight?.id ?? null);
    afterBox.body.append(reflyRow, reflyMsg, photos.el, replay.el);
    const legend = el('div', { class: 'muted fly-legend' });
    legend.innerHTML =
      '<span class="fly-dot" style="background:#a0a8b2"></span> pending <span class="fly-dot" style="background:#ffd400"></span> current <span class="fly-dot" style="background:#00b140"></span> reached <span class="fly-dot" style="background:#e8112d"></span> skipped · dashed: reassigned';
    const head = el('div', { class: 'plan-row' });
    head.append(stateLine, stop);
    flightBox.append(head, cmdRow, cmdMsg, legend, live.el, afterBox.box);
    const zoneKey = el('div', { class: 'zone-legend fly-zone-legend', 'data-testid': 'fly-zone-legend' });
    zoneKey.innerHTML = zoneLegendHtml();
    body.append(title, zoneKey, otherPlan, listRow, create.box, flightBox);

    // --- the mission's flights that have not ended
    let active: Flight[] = [];
    let activeMission: number | null = null;
    let activeTimer: number | null = null;
    let activeSeq = 0;
    const missionOf = (): number | null => app.state.missionId ?? (plan?.job.mission_id as number | undefined) ?? null;
    const renderActive = () => {
      activeBox.replaceChildren();
      activeBox.hidden = active.length === 0;
      if (!active.length) return;
      activeBox.append(el('div', { class: 'fly-active-head' }, `● ${active.length === 1 ? 'A flight has' : `${active.length} flights have`} not ended`));
      for (const f of active) {
        const row = el('div', { class: 'fly-active-flight', 'data-testid': 'fly-active-flight', 'data-id': String(f.id), 'data-plan': String(f.plan_id), 'data-state': f.state });
        const following = flight?.id === f.id;
        row.classList.toggle('fly-active-following', following);
        const where = f.plan_id === app.state.planId ? 'the open plan' : `plan #${f.plan_id}${app.state.planId !== null ? ', not the open plan' : ''}`;
        row.append(el('span', { class: 'fly-live-dot', 'aria-hidden': 'true' }), el('span', { class: 'fly-active-text' }, `Flight #${f.id} — ${f.state}${f.simulated ? ' (simulated)' : ''} · ${where}`));
        if (following) row.append(el('span', { class: 'fly-active-tag' }, 'shown'));
        else {
          const b = el('button', { type: 'button', class: 'plan-small', 'data-testid': 'fly-active-follow' }, 'Follow');
          b.addEventListener('click', () => void followFlight(f));
          row.append(b);
        }
        activeBox.append(row);
      }
    };
    const refreshActive = async (): Promise<Flight[]> => {
      const m = missionOf();
      const seq = ++activeSeq;
      if (m === null) {
        active = [];
        activeMission = null;
        renderActive();
        return active;
      }
      try {
        const items = (await api.get<{ items: Flight[] }>(`/missions/${m}/flights`)).items ?? [];
        if (seq !== activeSeq) return active;
        active = items.filter((f) => !flightEnded(f.state));
        activeMission = m;
      } catch {
        if (seq !== activeSeq) return active;
        active = []; // a server without the route: the plan's own list still works
      }
      renderActive();
      scheduleActive();
      return active;
    };
    const scheduleActive = () => {
      if (activeTimer !== null) clearTimeout(activeTimer);
      activeTimer = null;
      if (!visible || activeMission === null) return;
      activeTimer = window.setTimeout(() => void refreshActive(), active.length ? 3000 : 10000);
    };
    /** Shows a flight of any plan of the mission: its plan in this tab, then the flight. */
    const followFlight = async (f: Flight) => {
      if (plan?.id === f.plan_id) await listFlights(f.id);
      else await setPlan(f.plan_id, f.id);
    };
    const updateOtherPlan = () => {
      const open = app.state.planId;
      otherPlan.replaceChildren();
      otherPlan.hidden = !plan || open === null || plan.id === open;
      if (otherPlan.hidden) return;
      otherPlan.append(document.createTextNode(`This tab shows plan #${plan!.id}${flight ? `, flown by flight #${flight.id}` : ''}; the mission's open plan is #${open}. `));
      const b = el('button', { type: 'button', class: 'plan-small', 'data-testid': 'fly-open-plan' }, `Show plan #${open}`);
      b.addEventListener('click', () => void setPlan(open, 'none'));
      otherPlan.append(b);
    };

    // --- commands
    const send = async (command: string, extra: { uav?: string; reassignment?: number } = {}, quiet = false): Promise<void> => {
      const f = flight;
      if (!f) return;
      const req: Record<string, unknown> = { command };
      if (extra.uav) req.uav = extra.uav;
      if (extra.reassignment !== undefined) req.reassignment = extra.reassignment;
      if (!quiet) {
        cmdMsg.className = 'fly-message';
        cmdMsg.textContent = `${command}${extra.uav ? ` ${extra.uav}` : ''}: sent…`;
      }
      try {
        const r = await api.post<Flight>(`/flights/${f.id}/commands`, req);
        if (!quiet) {
          cmdMsg.textContent = `${command}${extra.uav ? ` ${extra.uav}` : ''}: queued`;
          lastCommand = { command, reassignment: extra.reassignment };
        }
        if (r && r.id === flight?.id) applyFlight(r);
      } catch (e) {
        cmdMsg.className = quiet ? 'fly-message muted' : 'fly-message plan-error';
        cmdMsg.textContent = `${command}: ${errorText(e as ApiError)}`;
      }
    };

    // --- applying a flight update
    const frameOf = (u: FlightUav): UavFrame => ({
      uav: u.uav,
      lat: u.position ? u.position.lat : null,
      lon: u.position ? u.position.lon : null,
      heading: u.position?.heading_deg ?? 0,
      statuses: u.waypoints ?? '',
      trail: Array.isArray(u.trail) ? u.trail.filter((p) => p.length >= 2).map((p) => [p[1], p[0]] as [number, number]) : null,
      lost: u.link?.state === 'lost',
      phase: u.phase,
      missions: u.missions ?? [],
    });
    const drawFlight = (f: Flight) => {
      if (!visible || replay.active) return;
      for (const u of f.uavs) layers.update(frameOf(u));
    };
    const applyFlight = (f: Flight) => {
      if (!flight || f.id !== flight.id) return;
      const wasEnded = flightEnded(flight.state);
      const ended = flightEnded(f.state);
      // an ended flight never flies again: a late answer (a list polled before the end, arriving after
      // the event that ended it) must not bring back its last live state
      if (wasEnded && !ended) return;
      // the list omits waypoints: keep the last known statuses
      flight = f;
      stateLine.dataset.state = f.state;
      const out = flightOutcome(f);
      stateLine.dataset.outcome = out.outcome;
      stateLine.classList.toggle('fly-state-lost', out.outcome.endsWith('-lost'));
      stateLine.textContent = `Flight #${f.id} — ${out.text}${f.simulated ? ' (simulated fleet)' : ''}`;
      // a command's "queued" gives way to what became of it
      if (lastCommand?.reassignment !== undefined) {
        const r = (f.reassignments ?? []).find((x) => x.id === lastCommand!.reassignment);
        if (r && r.state !== 'offered') {
          cmdMsg.className = 'fly-message';
          cmdMsg.textContent = `Reassignment #${r.id}: ${r.state}.`;
          lastCommand = null;
        }
      } else if (lastCommand && ended) {
        cmdMsg.textContent = '';
        lastCommand = null;
      }
      for (const b of cmdButtons.values()) b.disabled = ended;
      stop.disabled = ended;
      live.update(f);
      drawFlight(f);
      replay.setFlight(f.id, ended);
      const opt = flightSel.querySelector<HTMLOptionElement>(`option[value="${f.id}"]`);
      if (opt) opt.textContent = flightLabel(f);
      if (autoStart === f.id) {
        if (f.state === 'ready') {
          autoStart = null;
          void send('start', {}, true);
        } else if (f.state === 'flying' || ended) autoStart = null;
      }
      if (ended && !wasEnded) {
        void refreshCoverage(true);
        void refreshActive();
      }
    };

    // --- the flown coverage: overlay and PoC
    const refreshCoverage = async (once = false) => {
      const f = flight;
      if (!f) return;
      // only the newest request's answer is shown: the periodic one still under way when the flight ends
      // must not overwrite the final coverage asked for at the end
      const seq = ++coverageSeq;
      try {
        const c = await api.get<FlightCoverage>(`/flights/${f.id}/coverage`);
        if (flight?.id !== f.id || seq !== coverageSeq) return;
        replay.showCoverage(c);
        if (c.bounds && visible) layers.setCoverage(`${API}/flights/${f.id}/coverage.png?v=${Date.now()}`, c.bounds);
      } catch (e) {
        if (e instanceof ApiError && e.status === 404 && flight?.id === f.id) {
          replay.showCoverage(null); // this server does not compute the flown coverage
          return;
        }
        /* not yet: the next round */
      }
      if (!once) scheduleCoverage();
    };
    const scheduleCoverage = () => {
      if (coverageTimer !== null) clearTimeout(coverageTimer);
      coverageTimer = null;
      if (!flight || !visible || flightEnded(flight.state)) return;
      coverageTimer = window.setTimeout(() => void refreshCoverage(), COVERAGE_MS);
    };

    // --- choosing a flight
    const follow = (f: Flight | null) => {
      unwatch?.();
      unwatch = null;
      replay.close();
      live.clear();
      layers.reset();
      if ((f?.id ?? null) !== (flight?.id ?? null)) photos.clear(); // another flight: its photos go
      flight = f;
      flightBox.hidden = f === null;
      cmdMsg.textContent = '';
      replay.setFlight(f?.id ?? null, f ? flightEnded(f.state) : false);
      if (!f) return;
      flightSel.value = String(f.id);
      renderActive();
      updateOtherPlan();
      create.box.open = false; // the flight's panel gets the room; "New flight" opens again on a click
      applyFlight(f);
      unwatch = events.watchFlight(
        f.id,
        (x) => applyFlight(x),
        (e) => {
          cmdMsg.className = 'fly-message plan-error';
          cmdMsg.textContent = `Flight #${f.id} cannot be followed: ${errorText(e)}`;
        },
      );
      void refreshCoverage();
    };

    const listFlights = async (select: number | 'newest' | 'keep' | 'auto' | 'none') => {
      if (!plan) return;
      const p = plan;
      let items: Flight[];
      try {
        items = (await api.get<{ items: Flight[] }>(`/plans/${p.id}/flights`)).items ?? [];
      } catch (e) {
        if (plan === p) createMsg.textContent = `The plan's flights cannot be listed: ${errorText(e as ApiError)}`;
        return;
      }
      if (plan !== p) return;
      flightSel.replaceChildren(el('option', { value: '' }, items.length ? `${items.length} flight${items.length === 1 ? '' : 's'}` : 'no flights yet'));
      for (const f of items) flightSel.append(el('option', { value: String(f.id), 'data-state': f.state }, flightLabel(f)));
      if (items.length === 0) create.box.open = true;
      if (select === 'auto') {
        // a flight of this plan that has not ended first; else one of another plan of the mission (the
        // aircraft in the air), else this plan's newest
        const mine = items.find((f) => !flightEnded(f.state));
        if (!mine) {
          const elsewhere = (await refreshActive()).find((f) => f.plan_id !== p.id);
          if (plan !== p) return;
          if (elsewhere) {
            void setPlan(elsewhere.plan_id, elsewhere.id);
            return;
          }
        }
        select = mine ? mine.id : 'newest';
      }
      const want = select === 'newest' ? items[0]?.id : select === 'keep' ? flight?.id : select === 'none' ? undefined : select;
      if (want === undefined || want === null) {
        flightSel.value = '';
        return;
      }
      if (want === flight?.id) {
        flightSel.value = String(want);
        return;
      }
      try {
        follow(await api.get<Flight>(`/flights/${want}`));
      } catch (e) {
        createMsg.textContent = `Flight #${want} cannot be read: ${errorText(e as ApiError)}`;
      }
    };
    flightSel.addEventListener('change', () => {
      const id = Number(flightSel.value);
      if (id > 0) void listFlights(id);
      else follow(null);
    });

    // --- creating a flight
    const settings = (): Record<string, unknown> => ({
      auto_reassign: autoReassign.checked,
      separation_m: Number(separation.value),
      deviation_m: Number(deviation.value),
      low_battery_pct: Number(lowBattery.value),
      link_timeout_s: Number(linkTimeout.value),
      reassign_after_s: Number(reassignAfter.value),
      waypoint_retries: Number(waypointRetries.value),
      reassign_from: reassignFrom.value,
    });
    const createFlight = async (req: Record<string, unknown>, button: HTMLButtonElement, startAfter: boolean) => {
      if (!plan) return;
      button.disabled = true;
      createMsg.className = 'fly-message';
      createMsg.textContent = 'Creating the flight…';
      try {
        const f = await api.post<Flight>(`/plans/${plan.id}/flights`, { ...req, ...settings() });
        createMsg.textContent = `Flight #${f.id} created.`;
        if (startAfter) autoStart = f.id;
        follow(f);
        void refreshActive();
        void listFlights('keep');
        if (startAfter && (f.state === 'created' || f.state === 'ready')) {
          if (f.state === 'ready') {
            autoStart = null;
            await send('start', {}, true);
          } else await send('upload', {}, true);
        }
      } catch (e) {
        createMsg.className = 'fly-message plan-error';
        createMsg.textContent = `The flight was not created: ${errorText(e as ApiError)}`;
      } finally {
        button.disabled = false;
      }
    };
    simulate.addEventListener('click', () => {
      const sim: Record<string, unknown> = { speedup: Number(speedup.value) };
      try {
        const fail = failSpec(Number(failUav.value), Number(failAt.value), failKind.value);
        if (fail) sim.fail = fail;
      } catch (e) {
        createMsg.className = 'fly-message plan-error';
        createMsg.textContent = (e as Error).message;
        return;
      }
      // telemetry kept once per simulated second, as a real flight's at the default 1 s (the server's
      // floor is 0.05 s), so that the replay is as detailed at any speed-up
      const logPeriod = Math.min(1, Math.max(0.05, 1 / Math.max(1, Number(speedup.value) || 1)));
      void createFlight({ simulate: sim, log_period_s: Math.round(logPeriod * 1000) / 1000 }, simulate, true);
    });
    connect.addEventListener('click', () => {
      const vehicles = [...vehicleRows.querySelectorAll<HTMLElement>('.fly-vehicle')]
        .filter((r) => r.querySelector<HTMLInputElement>('[data-testid=fly-vehicle-on]')!.checked)
        .map((r) => ({
          uav: r.dataset.uav!,
          endpoint: r.querySelector<HTMLInputElement>('[data-testid=fly-endpoint]')!.value.trim(),
          listen: r.querySelector<HTMLInputElement>('[data-testid=fly-listen]')!.checked,
          sysid: Number(r.querySelector<HTMLInputElement>('[data-testid=fly-sysid]')!.value),
          home_item: r.querySelector<HTMLInputElement>('[data-testid=fly-home-item]')!.checked,
        }));
      void createFlight({ vehicles }, connect, false);
    });

    // --- the plan
    const setPlan = async (planId: number | null, select: number | 'auto' | 'none' = 'auto') => {
      const seq = ++planSeq;
      follow(null);
      plan = null;
      none.hidden = planId !== null;
      body.hidden = planId === null;
      flightSel.replaceChildren();
      updateOtherPlan();
      if (planId === null) {
        layers.setPlan([], new Map());
      layers.setZones({ area: [], nfz: [] });
        return;
      }
      title.textContent = `Plan #${planId}…`;
      try {
        const [job, paths] = await Promise.all([api.get<Job>(`/plans/${planId}`), api.get<PathsGeoJson>(`/plans/${planId}/paths.geojson`)]);
        if (seq !== planSeq) return;
        const ids = ((job.result.uavs as { id: string }[] | undefined) ?? []).map((u) => u.id);
        const uavs = ids.map((id, i) => ({ id, colour: uavColour(i) }));
        const lines = planWaypoints(paths);
        plan = { id: planId, job, uavs, lines };
        title.textContent = `Plan #${planId} (mission #${job.mission_id}, revision ${job.revision}): ${uavs.length} UAV${uavs.length === 1 ? '' : 's'}`;
        layers.setPlan(uavs, lines);
        layers.setZones(zoneRings(paths));
        buildForms(uavs);
        if (visible) fit();
        updateOtherPlan();
        await listFlights(select);
        renderActive();
      } catch (e) {
        if (seq !== planSeq) return;
        title.textContent = `Plan #${planId} cannot be read: ${errorText(e as ApiError)}`;
      }
    };
    const buildForms = (uavs: { id: string; colour: string }[]) => {
      failUav.replaceChildren(el('option', { value: '0' }, 'none'));
      uavs.forEach((u, i) => failUav.append(el('option', { value: String(i + 1) }, `UAV ${u.id}`)));
      vehicleRows.replaceChildren();
      uavs.forEach((u, i) => {
        const row = el('div', { class: 'fly-vehicle', 'data-uav': u.id, 'data-testid': 'fly-vehicle' });
        const on = el('input', { type: 'checkbox', 'data-testid': 'fly-vehicle-on', 'aria-label': `Fly ${u.id}` });
        on.checked = true;
        const sw = el('span', { class: 'plan-swatch' });
        sw.style.background = u.colour;
        const name = el('label', { class: 'fly-vehicle-name' });
        name.append(on, sw, document.createTextNode(u.id));
        const endpoint = el('input', { type: 'text', value: `udp:127.0.0.1:${14550 + i}`, 'data-testid': 'fly-endpoint', 'aria-label': `${u.id} endpoint`, class: 'fly-endpoint' });
        const listen = el('input', { type: 'checkbox', 'data-testid': 'fly-listen', 'aria-label': `${u.id}: listen` });
        listen.checked = true;
        const listenL = el('label', { class: 'plan-check', title: 'listen: bind the port and wait for the vehicle; else send to it' });
        listenL.append(listen, document.createTextNode('listen'));
        const sysid = numberInput('fly-sysid', String(i + 1), { min: '1', max: '255', step: '1', 'aria-label': `${u.id} system id` });
        const home = el('input', { type: 'checkbox', 'data-testid': 'fly-home-item' });
        const homeL = el('label', { class: 'plan-check', title: 'ArduPilot: mission item 0 is home' });
        homeL.append(home, document.createTextNode('home item'));
        row.append(name, endpoint, listenL, labelled('sysid', sysid), homeL);
        vehicleRows.append(row);
      });
    };
    const fit = () => {
      if (!plan || fitted === plan.id) return;
      const b = layers.bounds();
      if (b) app.map.fitBounds(b, { padding: [20, 20], animate: false });
      fitted = plan.id;
    };

    let seenPlan: number | null = app.state.planId;
    let seenMission: number | null = app.state.missionId;
    app.subscribe((s) => {
      const missionChanged = s.missionId !== seenMission;
      seenMission = s.missionId;
      if (s.planId !== seenPlan || missionChanged) {
        seenPlan = s.planId;
        const keep = flight !== null && !flightEnded(flight.state) && !missionChanged && (s.missionId === null || flight.mission_id === undefined || flight.mission_id === s.missionId);
        if (keep) {
          // the aircraft in the air stay on screen: the new plan is one click away
          updateOtherPlan();
          void refreshActive();
        } else if (s.planId !== (plan?.id ?? null) && s.planId !== pendingPlan) {
          pendingPlan = s.planId;
          void setPlan(s.planId).finally(() => (pendingPlan = undefined));
        } else if (missionChanged) void refreshActive();
      }
    });
    let pendingPlan: number | null | undefined = undefined;

    this.show = () => {
      visible = true;
      layers.show();
      fit();
      if (flight && !replay.active) drawFlight(flight);
      if (flight) void refreshCoverage();
      if (plan === null && app.state.planId !== null && pendingPlan === undefined) void setPlan(app.state.planId);
      void refreshActive();
    };
    this.hide = () => {
      visible = false;
      layers.hide();
      photos.clear();
      if (coverageTimer !== null) clearTimeout(coverageTimer);
      coverageTimer = null;
      if (activeTimer !== null) clearTimeout(activeTimer);
      activeTimer = null;
    };
    void setPlan(app.state.planId);
  },
};
