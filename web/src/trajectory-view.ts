// The trajectory of one UAV against time (issue 33, Mondinelli 2025 §4): the server's `trajectory_plot`
// export (GET /plans/{id}/exports/trajectory_plot?uav=ID&method=M, a PNG with position, velocity and
// acceleration and the limits dashed) shown in the Plan tab, per UAV and per method: today's lines and
// fillets, or the thesis's piecewise polynomials (order 5 at the UAV's speed). Made on request and cached
// by the server, like every export.
import { API, ApiError } from './api.ts';
import { fetchFile } from './exports.ts';
import { el, errorText } from './job-ui.ts';

export const trajectoryMethods = [
  ['fillet-lines', 'Lines and fillets'],
  ['polynomial', 'Polynomials (order 5)'],
] as const;

/** The plot's URL for a UAV and a method. */
export function trajectoryPlotUrl(planId: number, uav: string, method: string): string {
  return `${API}/plans/${planId}/exports/trajectory_plot?` + new URLSearchParams({ uav, method }).toString();
}

/**
 * The plot at the size it was drawn (scaled down only to fit the window) over the page, the way the
 * side-by-side maps open; Close, Escape or a click beside it ends it.
 */
function enlargePlot(src: string, title: string): void {
  const overlay = el('div', { class: 'plan-overlay', 'data-testid': 'trajectory-enlarged', role: 'dialog', 'aria-label': title });
  const bar = el('div', { class: 'plan-overlay-bar' });
  const close = el('button', { type: 'button', 'data-testid': 'trajectory-enlarged-close' }, 'Close');
  bar.append(el('strong', {}, title), close);
  const frame = el('div', { class: 'plan-trajectory-frame' });
  const big = el('img', { class: 'plan-trajectory-big', 'data-testid': 'trajectory-plot-big', alt: title, src });
  frame.append(big);
  overlay.append(bar, frame);
  const end = () => {
    overlay.remove();
    document.removeEventListener('keydown', onKey);
  };
  const onKey = (e: KeyboardEvent) => {
    if (e.key === 'Escape') end();
  };
  close.addEventListener('click', end);
  frame.addEventListener('click', (e) => {
    if (e.target === frame) end();
  });
  document.addEventListener('keydown', onKey);
  document.body.append(overlay);
  close.focus();
}

/** The panel: a UAV select, a method select, the plot and a button that shows it at full size. */
export function trajectoryPanel(planId: number, uavs: string[]): HTMLElement {
  const box = el('div', { class: 'plan-trajectory', 'data-testid': 'trajectory-panel' });
  const sel = el('select', { 'data-testid': 'trajectory-uav', 'aria-label': 'UAV' });
  for (const u of uavs) sel.append(el('option', { value: u }, u));
  const method = el('select', { 'data-testid': 'trajectory-method', 'aria-label': 'trajectory method' });
  for (const [value, label] of trajectoryMethods) method.append(el('option', { value }, label));
  const img = el('img', {
    class: 'plan-trajectory-plot',
    'data-testid': 'trajectory-plot',
    alt: 'position, velocity and acceleration against time',
  }) as HTMLImageElement;
  img.hidden = true;
  const enlarge = el('button', { type: 'button', class: 'plan-small', 'data-testid': 'trajectory-enlarge', title: 'Show the plot at full size' }, 'Enlarge');
  enlarge.hidden = true;
  const note = el('p', { class: 'define-small muted', 'data-testid': 'trajectory-note' });
  box.append(sel, method, enlarge, note, img);
  let seq = 0;
  let shown = '';
  const show = async () => {
    const mine = ++seq;
    note.textContent = `Making the ${method.selectedOptions[0]?.textContent ?? ''} trajectory of ${sel.value}…`;
    try {
      const file = await fetchFile(trajectoryPlotUrl(planId, sel.value, method.value), 'trajectory.png');
      if (mine !== seq) return;
      if (shown) URL.revokeObjectURL(shown);
      shown = URL.createObjectURL(file.blob);
      img.src = shown;
      img.hidden = false;
      img.dataset.uav = sel.value;
      img.dataset.method = method.value;
      enlarge.hidden = false;
      note.textContent = `${sel.value}: position, velocity and acceleration against time; the limits dashed.`;
    } catch (e) {
      if (mine === seq) {
        img.hidden = true;
        enlarge.hidden = true;
        note.textContent = `No trajectory plot: ${errorText(e as ApiError)}`;
      }
    }
  };
  const open = () => {
    if (shown && !img.hidden) enlargePlot(shown, `${img.dataset.uav}: trajectory (${method.selectedOptions[0]?.textContent ?? ''})`);
  };
  enlarge.addEventListener('click', open);
  img.addEventListener('click', open);
  sel.addEventListener('change', () => void show());
  method.addEventListener('change', () => void show());
  if (uavs.length > 0) void show();
  else note.textContent = 'No UAV flies in this plan.';
  return box;
}
