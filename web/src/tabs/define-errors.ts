// The Define tab's form layout and its errors (issue 11): sections and field rows that carry the
// `data-anchor` names of the document paths they edit, the numbers read from and written to their inputs,
// and the server's errors shown beside the field they name (or, failing one, in the general box).
import { el } from '../dom.ts';
import { fieldLabel, humanMessage, matchField, type MissionDoc } from '../mission-doc.ts';

/** an input's number; undefined when it is empty or not a number */
export function num(s: string): number | undefined {
  if (s.trim() === '') return undefined;
  const x = Number(s);
  return Number.isFinite(x) ? x : undefined;
}

export function round(x: number, digits: number): number {
  const f = 10 ** digits;
  return Math.round(x * f) / f;
}

/** a titled section at the end of the panel */
export function section(panel: HTMLElement, title: string): HTMLElement {
  const s = el('section', { class: 'define-section' });
  s.appendChild(el('h3', {}, title));
  panel.appendChild(s);
  return s;
}

/** a labelled input row; `anchors` are the document paths it edits (where their errors are shown) */
export function field(parent: HTMLElement, label: string, anchors: string, input: HTMLElement, unit?: string): HTMLElement {
  const row = el('label', { class: 'define-field', 'data-anchor': anchors });
  row.appendChild(el('span', { class: 'define-label' }, label));
  row.appendChild(input);
  if (unit) row.appendChild(el('span', { class: 'define-unit' }, unit));
  parent.appendChild(row);
  return row;
}

export interface ErrorsHost {
  doc(): MissionDoc;
  /** the side overlap as entered (in %) */
  overlap(): string;
}

/** the errors of the mission document shown in the panel: beside the fields, or in the general box */
export class DefineErrors {
  readonly general = el('div', { class: 'define-general', 'data-testid': 'general-error', role: 'alert', hidden: '' });

  constructor(
    private panel: HTMLElement,
    private host: ErrorsHost,
  ) {}

  private anchors(): Map<string, HTMLElement> {
    const m = new Map<string, HTMLElement>();
    for (const a of this.panel.querySelectorAll<HTMLElement>('[data-anchor]'))
      for (const name of (a.dataset.anchor ?? '').split(/\s+/)) if (name && !m.has(name)) m.set(name, a);
    return m;
  }

  /** show a server error next to the input that edits the field it names, or in the general box */
  show(field: string, message: string): void {
    const anchors = this.anchors();
    const match = matchField(field, anchors.keys());
    // in words: the field as the form names it ("uav2 share", "Altitude"), its path in the tooltip
    const doc = this.host.doc();
    const label = fieldLabel(field, doc);
    const text = `${label ? `${label}: ` : ''}${humanMessage(field, message, doc)}`;
    if (!match) {
      this.showGeneral(text, field);
      return;
    }
    const target = anchors.get(match)!;
    target.classList.add('define-invalid');
    // a field inside a closed fold (a UAV's flight limits): open it, so that the error is seen
    const fold = target.closest('details');
    if (fold) fold.open = true;
    // a problem of the shares as a whole marks every share
    if (field === 'uavs' && /share/i.test(message))
      this.panel.querySelectorAll('.define-uavs .define-share').forEach((x) => x.classList.add('define-invalid'));
    // overlaps are fractions in the file, percentages here: say so
    const hint = /overlap$/.test(field) ? ` (entered here in %: ${this.host.overlap()} %)` : '';
    const box = el('div', { class: 'define-field-error', 'data-testid': 'field-error', 'data-field': field, role: 'alert', title: field }, text + hint);
    if (target.tagName === 'SECTION') target.querySelector('h3')!.after(box);
    else if (target.classList.contains('define-inline') || target.classList.contains('define-share')) target.closest('.define-uav')!.appendChild(box);
    else target.after(box);
    if (target.closest('.tab-panel') && !(target.closest('.tab-panel') as HTMLElement).hidden) box.scrollIntoView({ block: 'nearest' });
  }

  clear(): void {
    this.panel.querySelectorAll('[data-testid="field-error"]').forEach((e) => e.remove());
    this.panel.querySelectorAll('.define-invalid').forEach((e) => e.classList.remove('define-invalid'));
  }

  showGeneral(message: string, field = ''): void {
    this.general.hidden = false;
    this.general.dataset.field = field;
    this.general.textContent = message;
    this.general.title = field;
  }

  clearGeneral(): void {
    this.general.hidden = true;
    this.general.textContent = '';
  }
}
