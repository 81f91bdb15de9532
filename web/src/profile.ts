// The ground profile under a UAV's flight (issue 31): GET /plans/{id}/profile?uav=ID drawn on a canvas:
// the ground (filled), the flight's height, and the band of heights above ground over the coverage. Shown
// in the Plan tab for plans with a terrain block.
import { api, ApiError } from './api.ts';
import { el, errorText } from './job-ui.ts';

export interface Profile {
  uav: string;
  length_m: number;
  altitude_m: number;
  tolerance_m: number;
  agl_min_m: number;
  agl_max_m: number;
  samples: [number, number, number, boolean][];
}

/** the chart of one profile on `canvas` (CSS pixels `w` x `h`) */
export function drawProfile(canvas: HTMLCanvasElement, p: Profile, w: number, h: number): void {
  const dpr = window.devicePixelRatio || 1;
  canvas.width = Math.round(w * dpr);
  canvas.height = Math.round(h * dpr);
  canvas.style.width = `${w}px`;
  canvas.style.height = `${h}px`;
  const g = canvas.getContext('2d');
  if (!g || p.samples.length < 2) return;
  g.scale(dpr, dpr);
  const pad = { l: 44, r: 8, t: 8, b: 22 };
  let lo = Infinity, hi = -Infinity;
  for (const [, ground, flight] of p.samples) {
    lo = Math.min(lo, ground);
    hi = Math.max(hi, flight, ground);
  }
  lo = Math.floor(lo - 5);
  hi = Math.ceil(hi + 5);
  const X = (s: number) => pad.l + (s / Math.max(p.length_m, 1)) * (w - pad.l - pad.r);
  const Y = (z: number) => pad.t + ((hi - z) / Math.max(hi - lo, 1)) * (h - pad.t - pad.b);
  g.clearRect(0, 0, w, h);
  // the ground, filled
  g.beginPath();
  g.moveTo(X(p.samples[0][0]), Y(lo));
  for (const [s, ground] of p.samples) g.lineTo(X(s), Y(ground));
  g.lineTo(X(p.samples[p.samples.length - 1][0]), Y(lo));
  g.closePath();
  g.fillStyle = '#c9b18a';
  g.fill();
  // the flight: coverage solid and dark, the rest thin
  for (const coverage of [false, true]) {
    g.beginPath();
    let pen = false;
    for (const [s, , flight, cov] of p.samples) {
      if (cov === coverage) {
        if (!pen) g.moveTo(X(s), Y(flight));
        else g.lineTo(X(s), Y(flight));
        pen = true;
      } else {
        pen = false;
      }
    }
    g.strokeStyle = coverage ? '#1f4e9c' : '#7f9bd1';
    g.lineWidth = coverage ? 2 : 1;
    g.stroke();
  }
  // axes
  g.fillStyle = '#444';
  g.font = '11px sans-serif';
  g.textAlign = 'right';
  for (const z of [lo, Math.round((lo + hi) / 2), hi]) g.fillText(`${z} m`, pad.l - 4, Y(z) + 4);
  g.textAlign = 'center';
  g.fillText(`${(p.length_m / 1000).toFixed(2)} km`, w - 30, h - 6);
  g.fillText('0', pad.l, h - 6);
}

/** the panel: a UAV select, the chart and the AGL band */
export function profilePanel(planId: number, uavs: string[]): HTMLElement {
  const box = el('div', { class: 'plan-profile', 'data-testid': 'profile-panel' });
  const sel = el('select', { 'data-testid': 'profile-uav', 'aria-label': 'UAV' });
  for (const u of uavs) sel.append(el('option', { value: u }, u));
  const canvas = el('canvas', { 'data-testid': 'profile-chart', role: 'img', 'aria-label': 'ground and flight heights' });
  const note = el('p', { class: 'define-small muted', 'data-testid': 'profile-band' });
  box.append(sel, canvas, note);
  let seq = 0;
  const show = async () => {
    const mine = ++seq;
    note.textContent = 'Loading the ground profile…';
    try {
      const p = await api.get<Profile>(`/plans/${planId}/profile?uav=${encodeURIComponent(sel.value)}`);
      if (mine !== seq) return;
      const width = Math.max(240, Math.min(box.clientWidth || 360, 520));
      drawProfile(canvas, p, width, 160);
      canvas.dataset.samples = String(p.samples.length);
      note.textContent =
        `Above ground over the coverage: ${p.agl_min_m.toFixed(1)}–${p.agl_max_m.toFixed(1)} m ` +
        `(asked ${p.altitude_m} m${p.tolerance_m > 0 ? ` ± ${p.tolerance_m} m` : ''}); ` +
        `${(p.length_m / 1000).toFixed(2)} km flown.`;
      note.dataset.aglMin = String(p.agl_min_m);
      note.dataset.aglMax = String(p.agl_max_m);
    } catch (e) {
      if (mine === seq) note.textContent = `No ground profile: ${errorText(e as ApiError)}`;
    }
  };
  sel.addEventListener('change', () => void show());
  requestAnimationFrame(() => void show());
  return box;
}
