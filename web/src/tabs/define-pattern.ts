// The Define tab's Pattern section (docs/patterns.md): area, corridor or structure; the corridor's width
// and the structure's numbers (its centre line and footprint are drawn on the map by define-map.ts), and
// the pattern options (crosshatch, turnaround, entry, alternate transects, camera in turns, obliques).
import { el } from '../dom.ts';
import {
  corridorOf,
  PATTERN_DEFAULTS,
  patternOf,
  structureOf,
  withCorridor,
  withPattern,
  withStructure,
  type MissionDoc,
  type PatternOptions,
  type PolygonCoords,
  type Position,
} from '../mission-doc.ts';
import { ObliqueControls, StructureControls, type ExtrasHost } from './define-extras.ts';
import { field, num, section } from './define-errors.ts';
import type { DefineMap } from './define-map.ts';

export interface PatternHost {
  doc(): MissionDoc;
  commit(d: MissionDoc): void;
  /** the corridor and footprint buttons, and the map drawn again */
  map: Pick<DefineMap, 'drawButton' | 'render'>;
}

export class PatternSection {
  private patternSelect: HTMLSelectElement;
  private widthInput: HTMLInputElement;
  private corridorRow: HTMLElement;
  private corridorInfo: HTMLElement;
  private patternInputs: Partial<Record<keyof PatternOptions, HTMLInputElement | HTMLSelectElement>> = {};
  private structureRow: HTMLElement;
  private structureControls: StructureControls;
  private obliqueControls: ObliqueControls;

  constructor(
    panel: HTMLElement,
    private host: PatternHost,
    /** the host of define-extras' controls (its commit draws the whole form again) */
    extras: ExtrasHost,
  ) {
    const sec = section(panel, 'Pattern');
    sec.dataset.anchor = 'corridor pattern';
    this.patternSelect = el('select', { 'data-testid': 'pattern-kind', 'aria-label': 'Pattern' });
    for (const [v, t] of [
      ['area', 'Area: a grid over the drawn polygons'],
      ['corridor', 'Corridor: lanes along a drawn line'],
      ['structure', 'Structure: orbits around a building’s walls'],
    ])
      this.patternSelect.appendChild(el('option', { value: v }, t));
    this.patternSelect.addEventListener('change', () => {
      const k = this.patternSelect.value;
      // the other kinds' geometry goes (area and corridor and structure exclude each other)
      if (k !== 'corridor' && this.host.doc().corridor !== undefined) this.host.commit(withCorridor(this.host.doc(), null, 0));
      if (k !== 'structure' && this.host.doc().structure !== undefined) this.host.commit(withStructure(this.host.doc(), null));
      this.render();
      this.host.map.render();
    });
    field(sec, 'Pattern', 'corridor structure', this.patternSelect);
    this.corridorRow = el('div', { class: 'define-corridor' });
    const tools = el('div', { class: 'define-tools' });
    tools.appendChild(
      this.host.map.drawButton('corridor', { 'data-testid': 'draw-corridor', title: 'Click the centre line’s vertices on the map; click the last one again to finish (Esc cancels)' }, 'Draw corridor line'),
    );
    this.corridorRow.appendChild(tools);
    this.widthInput = el('input', { type: 'number', min: '1', max: '5000', step: 'any', value: '100', 'data-testid': 'corridor-width' });
    this.widthInput.addEventListener('change', () => {
      const c = corridorOf(this.host.doc());
      const w = num(this.widthInput.value);
      if (c && w !== undefined) this.host.commit(withCorridor(this.host.doc(), c.line, w));
      this.host.map.render();
    });
    field(this.corridorRow, 'Width', 'corridor.width_m', this.widthInput, 'm');
    this.corridorInfo = el('p', { class: 'define-small muted', 'data-testid': 'corridor-info' });
    this.corridorRow.appendChild(this.corridorInfo);
    sec.appendChild(this.corridorRow);
    // the structure: its footprint drawn as a polygon, its height, standoff, safe height and roof pass
    this.structureRow = el('div', { class: 'define-structure-row' });
    const stools = el('div', { class: 'define-tools' });
    stools.appendChild(
      this.host.map.drawButton('footprint', { 'data-testid': 'draw-footprint', title: 'Click the building’s corners on the map; click the first one again to close it (Esc cancels)' }, 'Draw footprint'),
    );
    this.structureControls = new StructureControls(extras);
    this.structureRow.append(stools, this.structureControls.row);
    sec.appendChild(this.structureRow);
    // the options; a changed one writes the pattern block (defaults are left out)
    const opts = el('div', { class: 'define-pattern-options', 'data-testid': 'pattern-options' });
    const check = (key: keyof PatternOptions, label: string, title: string) => {
      const i = el('input', { type: 'checkbox', 'data-testid': `pattern-${key}`, title });
      i.addEventListener('change', () => this.host.commit(withPattern(this.host.doc(), { [key]: i.checked })));
      field(opts, label, `pattern.${key}`, i);
      this.patternInputs[key] = i;
    };
    check('crosshatch', 'Crosshatch', 'sweep every part twice, the second time at 90° (double grid)');
    const ta = el('input', { type: 'number', min: '0', max: '500', step: 'any', placeholder: '0', 'data-testid': 'pattern-turnaround_m', title: 'legs extend beyond the area by this much, camera off' });
    ta.addEventListener('change', () => this.host.commit(withPattern(this.host.doc(), { turnaround_m: num(ta.value) ?? 0 })));
    field(opts, 'Turnaround', 'pattern.turnaround_m', ta, 'm');
    this.patternInputs.turnaround_m = ta;
    const entry = el('select', { 'data-testid': 'pattern-entry' });
    for (const [v, t] of [
      ['auto', 'nearest the start'],
      ['nw', 'north-west'],
      ['ne', 'north-east'],
      ['sw', 'south-west'],
      ['se', 'south-east'],
    ])
      entry.appendChild(el('option', { value: v }, t));
    entry.addEventListener('change', () => this.host.commit(withPattern(this.host.doc(), { entry: entry.value as PatternOptions['entry'] })));
    field(opts, 'Entry', 'pattern.entry', entry);
    this.patternInputs.entry = entry;
    check('alternate_transects', 'Alternate transects', 'every other lane, then back for the rest (fixed-wing turns)');
    check('capture_in_turnaround', 'Camera in turns', 'keep the camera on in turns and turnarounds');
    this.obliqueControls = new ObliqueControls(extras);
    opts.appendChild(this.obliqueControls.row);
    sec.append(opts, el('p', { class: 'define-small muted' }, 'Corridors, obliques and the options need a lane planner (boustrophedon, or milp for corridors): see “uavcover planners”.'));
  }

  /** the document's pattern into the section */
  render(): void {
    const doc = this.host.doc();
    const c = corridorOf(doc);
    const st = structureOf(doc);
    const kind = c !== null ? 'corridor' : st !== null ? 'structure' : this.patternSelect.value;
    this.patternSelect.value = kind;
    const corridor = kind === 'corridor';
    this.corridorRow.hidden = !corridor;
    this.structureRow.hidden = kind !== 'structure';
    this.structureControls.render(doc);
    this.obliqueControls.render(doc);
    if (c) this.widthInput.value = String(c.width_m);
    this.corridorInfo.textContent = c
      ? `Centre line of ${c.line.length} vertices, ${c.width_m} m wide.`
      : 'No corridor yet: press “Draw corridor line” and click its vertices on the map.';
    const p = patternOf(doc) ?? PATTERN_DEFAULTS;
    for (const [k, i] of Object.entries(this.patternInputs) as [keyof PatternOptions, HTMLInputElement | HTMLSelectElement][]) {
      const v = p[k];
      if (i instanceof HTMLInputElement && i.type === 'checkbox') i.checked = v === true;
      else i.value = k === 'turnaround_m' && v === 0 ? '' : String(v);
    }
  }

  /** the corridor's centre line was drawn on the map */
  corridorDrawn(line: Position[]): void {
    this.host.commit(withCorridor(this.host.doc(), line, num(this.widthInput.value) ?? 100));
    this.render();
  }

  /** the building's footprint was drawn on the map (one polygon, else nothing) */
  footprintDrawn(polys: PolygonCoords[]): void {
    if (polys.length === 1) this.host.commit(withStructure(this.host.doc(), { ...this.structureControls.values(), footprint: [polys[0][0]] }));
    this.render();
  }
}
