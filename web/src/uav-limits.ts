// A UAV's flight limits in the Define tab (issue 32): endurance, acceleration, and the climb and descent
// speeds of the whole-flight time. They sit in a fold under the UAV's row; an empty input means the
// default (or the catalog UAV's endurance), which the server fills in (docs/mission-format.md).
import { el } from './dom.ts';

export interface LimitField {
  /** the mission's field of uavs[i] */
  key: 'endurance_min' | 'max_accel_mps2' | 'climb_mps' | 'descent_mps';
  label: string;
  unit: string;
  min: number;
  max: number;
  /** what the server uses when the field is not given */
  fallback: number;
}

/** the fields, their ranges and the server's defaults (src/mission: uavs[i].*) */
export const LIMIT_FIELDS: readonly LimitField[] = [
  { key: 'endurance_min', label: 'endurance', unit: 'min', min: 0.1, max: 10000, fallback: 25 },
  { key: 'max_accel_mps2', label: 'acceleration', unit: 'm/s²', min: 0.001, max: 100, fallback: 2 },
  { key: 'climb_mps', label: 'climb', unit: 'm/s', min: 0.1, max: 30, fallback: 3 },
  { key: 'descent_mps', label: 'descent', unit: 'm/s', min: 0.1, max: 30, fallback: 1.5 },
];

type Uav = Record<string, unknown>;

/** the value a field has for this UAV: its own, else the catalog's endurance, else the default */
export function effectiveLimit(uav: Uav, f: LimitField, catalogEndurance?: number): number {
  const own = uav[f.key];
  if (typeof own === 'number' && Number.isFinite(own)) return own;
  if (f.key === 'endurance_min' && typeof catalogEndurance === 'number') return catalogEndurance;
  return f.fallback;
}

/** the fold's one-line summary, e.g. "25 min · climb 3 m/s · descent 1.5 m/s"; a * marks what differs from the default */
export function limitsSummary(uav: Uav, catalogEndurance?: number): string {
  const part = (f: LimitField): string => {
    const v = effectiveLimit(uav, f, catalogEndurance);
    const mark = typeof uav[f.key] === 'number' ? '*' : '';
    return f.key === 'endurance_min' ? `${v} min${mark}` : `${f.label} ${v} ${f.unit}${mark}`;
  };
  return LIMIT_FIELDS.filter((f) => f.key !== 'max_accel_mps2')
    .map(part)
    .join(' · ');
}

/** "12.5" → 12.5, "" → undefined (the default), anything else → NaN, which the server refuses naming the field */
function parse(s: string): number | undefined {
  if (s.trim() === '') return undefined;
  return Number(s);
}

/**
 * The fold: a <details> whose inputs call `set` with a patch of the UAV (undefined = back to the
 * default). Each input is anchored at its field, so that a server error shows beside it.
 */
export function limitsFold(
  uav: Uav,
  index: number,
  set: (patch: Uav) => void,
  opts: { catalogEndurance?: number; open: boolean; onToggle: (open: boolean) => void },
): HTMLDetailsElement {
  const catalogEndurance = opts.catalogEndurance;
  const fold = el('details', { class: 'define-uav-limits', 'data-testid': 'uav-limits' });
  // the row is drawn again after every change: the fold keeps the state the operator gave it
  fold.open = opts.open;
  fold.addEventListener('toggle', () => opts.onToggle(fold.open));
  const summary = el('summary', { title: 'flight limits: endurance, acceleration, climb and descent speeds (empty = the default)' }, limitsSummary(uav, catalogEndurance));
  fold.appendChild(summary);
  const grid = el('div', { class: 'define-uav-limits-grid' });
  for (const f of LIMIT_FIELDS) {
    const fallback = f.key === 'endurance_min' && typeof catalogEndurance === 'number' ? catalogEndurance : f.fallback;
    const input = el('input', {
      type: 'number',
      min: String(f.min),
      max: String(f.max),
      step: 'any',
      value: typeof uav[f.key] === 'number' ? String(uav[f.key]) : '',
      placeholder: String(fallback),
      'aria-label': `${f.label} (${f.unit}), empty: ${fallback}`,
      'data-testid': `uav-${f.key.replace(/_/g, '-')}`,
    });
    input.addEventListener('change', () => set({ [f.key]: parse(input.value) }));
    const wrap = el('label', { class: 'define-inline', 'data-anchor': `uavs[${index}].${f.key}` });
    wrap.append(el('span', { class: 'define-unit define-limit-label' }, f.label), input, el('span', { class: 'define-unit' }, f.unit));
    grid.appendChild(wrap);
  }
  fold.appendChild(grid);
  return fold;
}
