// The Fly tab's live panel: one card per UAV (phase, progress, battery, ETA, link, altitude band,
// sortie k/n, waypoint retries, its own commands), the alerts, and the reassignment offers with Apply /
// Decline. Cards are built once per flight and their fields rewritten only when their text changes.
import { el } from './job-ui.ts';
import { countStatus, flightOutcome, formatEta, progressText, retriesText, type Flight, type FlightAlert, type FlightReassignment, type FlightUav } from './fly-model.ts';

/** Per-UAV commands (docs/flights.md), shown on each card. */
const UAV_COMMANDS: [string, string][] = [
  ['pause', 'Pause'],
  ['continue', 'Continue'],
  ['rtl', 'RTL'],
  ['land', 'Land'],
  ['resume', 'Resume'],
  ['next_sortie', 'Next sortie'],
];

const FIELDS = ['phase', 'progress', 'battery', 'eta', 'link', 'band', 'sortie', 'retries'] as const;
type Field = (typeof FIELDS)[number];

interface Card {
  box: HTMLElement;
  bar: HTMLProgressElement;
  fields: Record<Field, HTMLElement>;
  text: Record<string, string>;
}

export type SendCommand = (command: string, extra?: { uav?: string; reassignment?: number }) => void;

function set(card: Card, f: Field, text: string, state?: string): void {
  const key = `${text}|${state ?? ''}`;
  if (card.text[f] === key) return;
  card.text[f] = key;
  const e = card.fields[f];
  e.textContent = text;
  if (state !== undefined) e.dataset.state = state;
}

export class FlyPanel {
  readonly el = el('div', { class: 'fly-live' });
  private cards = new Map<string, Card>();
  private cardBox = el('div', { class: 'fly-cards', 'data-testid': 'fly-uav-cards' });
  private alerts = el('ul', { class: 'fly-alerts', 'data-testid': 'fly-alerts' });
  private offers = el('div', { class: 'fly-offers', 'data-testid': 'fly-reassignments' });
  private alertsKey = '';
  /** UAVs lost in this flight: their link-lost alerts stay on top, even once the flight ended */
  private lost = new Set<string>();
  private offersKey = '';

  constructor(
    private send: SendCommand,
    private colourOf: (uav: string) => string,
    private focus: (uav: string) => void,
  ) {
    const alertsHead = el('div', { class: 'fly-subhead' }, 'Alerts');
    this.el.append(this.offers, alertsHead, this.alerts, el('div', { class: 'fly-subhead' }, 'UAVs'), this.cardBox);
  }

  clear(): void {
    this.cards.clear();
    this.cardBox.replaceChildren();
    this.alerts.replaceChildren();
    this.offers.replaceChildren();
    this.alertsKey = this.offersKey = '';
  }

  update(f: Flight): void {
    const ended = f.state === 'done' || f.state === 'aborted';
    this.lost = new Set(flightOutcome(f).lost);
    const limit = f.config?.waypoint_retries;
    for (const u of f.uavs) this.updateCard(this.card(u.uav), u, ended, typeof limit === 'number' ? limit : undefined);
    this.updateAlerts(f.alerts ?? []);
    this.updateOffers(f.reassignments ?? [], ended);
  }

  private card(uav: string): Card {
    let c = this.cards.get(uav);
    if (c) return c;
    const box = el('div', { class: 'fly-card', 'data-testid': 'fly-uav-card', 'data-uav': uav });
    const head = el('div', { class: 'fly-card-head' });
    const sw = el('span', { class: 'plan-swatch' });
    sw.style.background = this.colourOf(uav);
    const phase = el('span', { class: 'fly-phase', 'data-field': 'phase' });
    const name = el('button', { type: 'button', class: 'fly-card-name', title: 'Show it on the map', 'data-testid': 'fly-uav-focus' }, uav);
    name.addEventListener('click', () => this.focus(uav));
    head.append(sw, name, phase);
    const bar = el('progress', { max: '1', value: '0', class: 'fly-progress' });
    const grid = el('div', { class: 'fly-card-grid' });
    const fields = { phase } as Record<Field, HTMLElement>;
    const labels: [Field, string][] = [
      ['progress', 'progress'],
      ['battery', 'battery'],
      ['eta', 'ETA'],
      ['link', 'link'],
      ['band', 'altitude'],
      ['sortie', 'sortie'],
      ['retries', 'retries'],
    ];
    for (const [f, label] of labels) {
      const v = el('span', { class: 'fly-value', 'data-field': f });
      fields[f] = v;
      grid.append(el('span', { class: 'muted' }, label), v);
    }
    const cmds = el('div', { class: 'fly-card-cmds' });
    for (const [cmd, label] of UAV_COMMANDS) {
      const b = el('button', { type: 'button', class: 'plan-small', 'data-testid': `fly-uav-cmd-${cmd}`, 'data-uav': uav }, label);
      b.addEventListener('click', () => this.send(cmd, { uav }));
      cmds.append(b);
    }
    box.append(head, bar, grid, cmds);
    this.cardBox.append(box);
    c = { box, bar, fields, text: {} };
    this.cards.set(uav, c);
    return c;
  }

  private updateCard(c: Card, u: FlightUav, ended: boolean, retryLimit?: number): void {
    set(c, 'phase', u.phase, u.phase);
    const { text, fraction: p } = progressText(u);
    if (c.bar.value !== p) c.bar.value = p;
    const reached = countStatus(u.waypoints, 'R');
    set(c, 'progress', text);
    if (c.box.dataset.reached !== String(reached)) c.box.dataset.reached = String(reached);
    const bat = u.battery_pct;
    set(c, 'battery', bat === null || bat === undefined ? '—' : `${bat.toFixed(0)} %`, bat === null || bat === undefined ? 'unknown' : bat < 25 ? 'low' : 'ok');
    set(c, 'eta', ended ? '—' : formatEta(u.eta_s));
    set(c, 'link', u.link?.state ?? '—', u.link?.state ?? 'unknown');
    const alt = u.position?.alt_m;
    set(c, 'band', `${u.band ?? '—'}${alt !== undefined && alt !== null ? ` · ${alt.toFixed(0)} m` : ''}`, u.band ?? 'unknown');
    set(c, 'sortie', u.sorties ? `${(u.sortie ?? 0) + 1}/${u.sorties}` : '—');
    const r = retriesText(u.retries, retryLimit);
    set(c, 'retries', r.text, r.state);
    for (const b of c.box.querySelectorAll<HTMLButtonElement>('.fly-card-cmds button')) b.disabled = ended;
  }

  private updateAlerts(alerts: FlightAlert[]): void {
    const key = JSON.stringify(alerts) + [...this.lost].join(',');
    if (key === this.alertsKey) return;
    this.alertsKey = key;
    this.alerts.replaceChildren();
    if (!alerts.length) {
      this.alerts.append(el('li', { class: 'muted' }, 'none'));
      return;
    }
    // active first, newest first
    const lostAlert = (a: FlightAlert) => a.kind === 'link_lost' && !!a.uav && this.lost.has(a.uav);
    const sorted = [...alerts].sort(
      (a, b) => Number(lostAlert(b)) - Number(lostAlert(a)) || Number(!!b.active) - Number(!!a.active) || String(b.since ?? '').localeCompare(String(a.since ?? '')),
    );
    for (const a of sorted.slice(0, 50)) {
      const li = el('li', { class: `fly-alert${a.active || lostAlert(a) ? ' fly-alert-active' : ''}`, 'data-active': String(!!a.active), 'data-testid': 'fly-alert', 'data-kind': a.kind, 'data-uav': a.uav ?? '' });
      const when = a.since ? new Date(a.since).toLocaleTimeString() : '';
      li.append(el('span', { class: 'fly-alert-kind' }, alertName(a.kind)), document.createTextNode(` ${a.uav ?? ''}${a.other ? `–${a.other}` : ''}: ${a.message ?? ''} `), el('span', { class: 'muted' }, `${when}${a.active ? '' : ' (cleared)'}`));
      this.alerts.append(li);
    }
  }

  private updateOffers(rs: FlightReassignment[], ended: boolean): void {
    const key = JSON.stringify(rs) + ended;
    if (key === this.offersKey) return;
    this.offersKey = key;
    this.offers.replaceChildren();
    for (const r of rs) {
      const box = el('div', { class: `fly-offer fly-offer-${r.state}`, 'data-testid': 'fly-reassignment', 'data-id': String(r.id), 'data-state': r.state });
      const to = (r.to ?? []).map((t) => `${t.uav} ${t.waypoints ?? '?'} wp${t.length_m !== undefined ? ` / ${(t.length_m / 1000).toFixed(2)} km` : ''}`).join(', ');
      box.append(
        el('div', {}, `Reassignment #${r.id}: ${r.failed_uav}'s remaining ${r.remaining_waypoints ?? '?'} waypoints${r.area_m2 !== undefined ? ` (${(r.area_m2 / 10000).toFixed(2)} ha)` : ''} → ${to || 'nobody'} — ${r.state}`),
      );
      if (r.state === 'offered' && !ended) {
        const row = el('div', { class: 'plan-row' });
        const apply = el('button', { type: 'button', class: 'plan-primary', 'data-testid': 'fly-reassign-apply' }, 'Apply');
        const decline = el('button', { type: 'button', 'data-testid': 'fly-reassign-decline' }, 'Decline');
        apply.addEventListener('click', () => this.send('reassign', { reassignment: r.id }));
        decline.addEventListener('click', () => this.send('decline', { reassignment: r.id }));
        row.append(apply, decline);
        box.append(row);
      }
      this.offers.append(box);
    }
  }
}

function alertName(kind: string): string {
  switch (kind) {
    case 'link_lost':
      return 'Link lost';
    case 'low_battery':
      return 'Low battery';
    case 'deviation':
      return 'Off path';
    case 'separation':
      return 'Too close';
    default:
      return kind.replace(/_/g, ' ');
  }
}
