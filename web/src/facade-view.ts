// The facade's coverage (issue 30, docs/patterns.md "Structure"): the structure scan's wall unrolled as a
// picture, one pixel per 0.5 m sample, coloured by how many photos see it (photogrammetry wants 3 or
// more), with the walls' corners marked, and the figures the server computed (plan.json's "facade").
import { el } from './job-ui.ts';

export interface FacadeJson {
  covered_share?: number;
  share_3plus?: number;
  shares?: number[];
  images?: number;
  wall_area_m2?: number;
  gsd_wall_cm_per_px?: number | null;
  standoff_m?: number;
  unrolled?: { cols: number; rows: number; wall_start_col?: number[]; views: string[] };
}

/** views 0, 1, 2, 3+ (the colours of the picture and its key) */
export const VIEW_COLOURS: [number, number, number][] = [
  [211, 47, 47],
  [245, 124, 0],
  [251, 192, 45],
  [56, 142, 60],
];

/** RGBA pixels of the unrolled wall: rows top first, a dark column at each wall's first column (pure). */
export function facadePixels(u: NonNullable<FacadeJson['unrolled']>): Uint8ClampedArray<ArrayBuffer> {
  const { cols, rows } = u;
  const px = new Uint8ClampedArray(new ArrayBuffer(cols * rows * 4));
  const corner = new Set((u.wall_start_col ?? []).filter((c) => c > 0));
  for (let r = 0; r < rows; r++) {
    const line = u.views[r] ?? '';
    for (let c = 0; c < cols; c++) {
      const v = Math.min(3, Math.max(0, line.charCodeAt(c) - 48 || 0));
      const [R, G, B] = corner.has(c) ? [40, 40, 40] : VIEW_COLOURS[Number.isFinite(v) ? v : 0];
      const k = (r * cols + c) * 4;
      px[k] = R;
      px[k + 1] = G;
      px[k + 2] = B;
      px[k + 3] = 255;
    }
  }
  return px;
}

export function facadePanel(f: FacadeJson): HTMLElement {
  const box = el('div', { class: 'facade-panel', 'data-testid': 'facade-panel' });
  const pct = (x: number | undefined) => (x === undefined ? '—' : `${(x * 100).toFixed(1)} %`);
  box.dataset.covered = String(f.covered_share ?? '');
  box.append(
    el(
      'p',
      { class: 'muted' },
      `Facade: ${pct(f.covered_share)} of ${Math.round(f.wall_area_m2 ?? 0).toLocaleString('en')} m² of wall seen, ${pct(f.share_3plus)} by 3 or more photos` +
        (f.images !== undefined ? `, ${f.images} photos` : '') +
        (typeof f.gsd_wall_cm_per_px === 'number' ? `, ${f.gsd_wall_cm_per_px.toFixed(2)} cm/px on the wall` : '') +
        '.',
    ),
  );
  const u = f.unrolled;
  if (u && u.cols > 0 && u.rows > 0 && u.views.length === u.rows) {
    const canvas = el('canvas', { class: 'facade-wall', 'data-testid': 'facade-wall', width: String(u.cols), height: String(u.rows), title: 'the wall unrolled: along the footprint counter-clockwise from its first corner, ground at the bottom' });
    const ctx = canvas.getContext('2d');
    if (ctx) ctx.putImageData(new ImageData(facadePixels(u), u.cols, u.rows), 0, 0);
    const key = el('div', { class: 'facade-key muted' });
    ['not seen', '1 photo', '2 photos', '3+ photos'].forEach((label, i) => {
      const sw = el('span', { class: 'facade-swatch' });
      sw.style.background = `rgb(${VIEW_COLOURS[i].join(',')})`;
      key.append(sw, el('span', {}, `${label} ${pct(f.shares?.[i])}`));
    });
    box.append(canvas, key);
  }
  return box;
}
