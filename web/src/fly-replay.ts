// After a flight: its log (GET /flights/{id}/log, page by page) replayed with a time slider and a play
// button (positions from the telemetry records, waypoint statuses from the waypoint records), the
// flown against the planned PoC (GET /flights/{id}/coverage), and the log as CSV and GeoJSON.
import { api, API, ApiError } from './api.ts';
import { buildReplay, positionAt, statusesAt, type FlightCoverage, type LogRecord, type Replay } from './fly-model.ts';
import type { FlyLayers } from './fly-layers.ts';
import { el, errorText } from './job-ui.ts';

/** Log records read per page, and at most this many pages (a 10-hour flight of 16 UAVs at 1 Hz). */
const PAGE = 1000;
const MAX_PAGES = 600;

export class FlyReplay {
  readonly el = el('div', { class: 'fly-replay', 'data-testid': 'fly-replay' });
  private status = el('div', { class: 'muted fly-replay-status', 'data-testid': 'fly-replay-status' });
  private poc = el('div', { class: 'fly-poc', 'data-testid': 'fly-poc' });
  private load = el('button', { type: 'button', 'data-testid': 'fly-replay-load' }, 'Replay the flight');
  private controls = el('div', { class: 'plan-row fly-replay-controls', hidden: '' });
  private play = el('button', { type: 'button', 'data-testid': 'fly-replay-play', class: 'plan-small' }, '▶');
  private speed = el('select', { 'data-testid': 'fly-replay-speed', 'aria-label': 'Replay speed' });
  private slider = el('input', { type: 'range', min: '0', max: '1000', step: 'any', value: '0', 'data-testid': 'fly-replay-slider', 'aria-label': 'Replay time', class: 'fly-replay-slider' });
  private clock = el('span', { class: 'fly-replay-clock', 'data-testid': 'fly-replay-clock' });
  private exports = el('div', { class: 'plan-row' });
  private replay: Replay | null = null;
  private flightId: number | null = null;
  private seq = 0;
  private timer: number | null = null;
  private lastFrame = 0;
  /** set while the replay drives the map (the live view is paused) */
  active = false;

  constructor(
    private layers: FlyLayers,
    private planned: () => Map<string, number>,
    private onActive: (active: boolean) => void,
  ) {
    for (const x of [1, 5, 20, 60]) this.speed.append(el('option', { value: String(x) }, `×${x}`));
    this.speed.value = '20';
    this.controls.append(this.play, this.slider, this.speed, this.clock);
    this.el.append(this.poc, this.exports, this.load, this.controls, this.status);
    this.load.addEventListener('click', () => void this.start());
    this.slider.addEventListener('input', () => {
      this.stopPlaying();
      this.frame();
    });
    this.play.addEventListener('click', () => (this.timer === null ? this.startPlaying() : this.stopPlaying()));
  }

  /** Shows flight `id` (ended or not): its exports and PoC; the replay is loaded on demand. */
  setFlight(id: number | null, ended: boolean): void {
    if (id !== this.flightId) {
      this.close();
      this.flightId = id;
      this.exports.replaceChildren();
      this.poc.replaceChildren();
      if (id !== null)
        for (const [ext, label] of [
          ['csv', 'log.csv'],
          ['geojson', 'log.geojson'],
        ])
          this.exports.append(el('a', { href: `${API}/flights/${id}/log.${ext}`, download: `flight-${id}.${ext}`, 'data-testid': `fly-export-${ext}`, class: 'fly-link' }, label));
    }
    this.load.hidden = id === null;
    this.load.textContent = ended ? 'Replay the flight' : 'Replay so far';
  }

  /** The flown and planned PoC; null: the server has no flown coverage. */
  showCoverage(c: FlightCoverage | null): void {
    if (!c) {
      this.poc.textContent = 'Flown coverage: not available from this server';
      return;
    }
    const pct = (v: number | null) => (v === null || v === undefined ? '—' : `${(100 * v).toFixed(1)} %`);
    this.poc.dataset.flown = String(c.flown_poc ?? '');
    this.poc.dataset.planned = String(c.planned_poc ?? '');
    this.poc.textContent = `Flown PoC ${pct(c.flown_poc)} · planned ${pct(c.planned_poc)}`;
  }

  /** Leaves replay mode (the live view takes the map back). */
  close(): void {
    this.seq++;
    this.stopPlaying();
    this.replay = null;
    this.controls.hidden = true;
    this.status.textContent = '';
    if (this.active) {
      this.active = false;
      this.onActive(false);
    }
  }

  private async start(): Promise<void> {
    const id = this.flightId;
    if (id === null) return;
    const seq = ++this.seq;
    this.load.disabled = true;
    const records: LogRecord[] = [];
    try {
      let after = 0;
      for (let page = 0; page < MAX_PAGES; page++) {
        this.status.textContent = `Reading the flight log… ${records.length} records`;
        const r = await api.get<{ items: LogRecord[]; next_after: number | null }>(`/flights/${id}/log?after=${after}&limit=${PAGE}`);
        if (seq !== this.seq) return;
        records.push(...r.items);
        if (r.next_after === null || r.next_after === undefined || !r.items.length) break;
        after = r.next_after;
      }
    } catch (e) {
      if (seq === this.seq) this.status.textContent = `The flight log cannot be read: ${errorText(e as ApiError)}`;
      return;
    } finally {
      this.load.disabled = false;
    }
    const replay = buildReplay(records, this.planned());
    this.replay = replay;
    const tracks = [...replay.uavs.values()].reduce((n, u) => n + u.track.length, 0);
    const changes = [...replay.uavs.values()].reduce((n, u) => n + u.changes.length, 0);
    this.status.textContent = `${records.length} records: ${tracks} positions, ${changes} waypoint changes, ${replay.events.length} events over ${((replay.t1 - replay.t0) / 1000).toFixed(0)} s`;
    this.el.dataset.records = String(records.length);
    this.controls.hidden = false;
    this.slider.value = '1000';
    if (!this.active) {
      this.active = true;
      this.onActive(true);
    }
    this.frame();
  }

  private timeOf(v: number): number {
    const r = this.replay!;
    return r.t0 + (v / 1000) * (r.t1 - r.t0);
  }

  /** Draws the replay at the slider's time. */
  private frame(): void {
    const r = this.replay;
    if (!r) return;
    const t = this.timeOf(Number(this.slider.value));
    for (const u of r.uavs.values()) {
      const p = positionAt(u, t);
      const trail = p ? u.track.slice(0, p.count).map((s) => [s.lat, s.lon] as [number, number]) : [];
      if (p) trail.push([p.lat, p.lon]);
      this.layers.update({ uav: u.uav, lat: p?.lat ?? null, lon: p?.lon ?? null, heading: p?.heading ?? 0, statuses: statusesAt(u, t), trail, lost: false, phase: 'replay' });
    }
    this.clock.textContent = `${new Date(t).toLocaleTimeString()} (+${((t - r.t0) / 1000).toFixed(0)} s)`;
    this.el.dataset.t = String(Math.round(t));
  }

  private startPlaying(): void {
    if (!this.replay) return;
    if (Number(this.slider.value) >= 1000) this.slider.value = '0';
    this.play.textContent = '❚❚';
    this.lastFrame = performance.now();
    const tick = () => {
      const r = this.replay;
      if (!r) return this.stopPlaying();
      const now = performance.now();
      const span = Math.max(1, r.t1 - r.t0);
      const v = Number(this.slider.value) + ((now - this.lastFrame) * Number(this.speed.value) * 1000) / span;
      this.lastFrame = now;
      this.slider.value = String(Math.min(1000, v));
      this.frame();
      if (v >= 1000) this.stopPlaying();
      else this.timer = window.setTimeout(tick, 100);
    };
    this.timer = window.setTimeout(tick, 100);
  }

  private stopPlaying(): void {
    if (this.timer !== null) clearTimeout(this.timer);
    this.timer = null;
    this.play.textContent = '▶';
  }
}
