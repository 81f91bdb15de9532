// The Define tab (issue 11): draw and edit the area and no-fly zones (geoman: vertex editing, holes by
// cutting, snapping; Esc, Ctrl-Z, Delete), UAVs from the catalog or by hand with draggable starts,
// shares that always sum to 100 %, camera/altitude/overlap with spacing, GSD and footprint computed by
// the server (POST /missions/validate), mode, planner and its parameters, seed; save revision by
// revision. The state's mission document is always what the operator sees.
import { el } from '../dom.ts';
import { DefineMap } from './define-map.ts';
import { api, ApiError } from '../api.ts';
import { panelTab, type App, type Tab } from '../state.ts';
import {
  corridorOf,
  newDraft,
  PATTERN_DEFAULTS,
  patternOf,
  structureOf,
  withCorridor,
  withPattern,
  withStructure,
  type MissionDoc,
  type PatternOptions,
} from '../mission-doc.ts';
import { fieldsFromSchema, paramsForSchema, renderSchemaForm, type PlannerSchema } from '../schema-form.ts';
import '../missions.css';
import '../define.css';
import { errorText } from './missions.ts';
import {
  FieldControls,
  ObjectiveControl,
  ObliqueControls,
  StructureControls,
  TerrainControls,
  WindControls,
  type DemEntry,
  type ExtrasHost,
} from './define-extras.ts';
import { CameraSection, type CatalogCamera } from './define-camera.ts';
import { DefineUavs, type CatalogUav } from './define-uavs.ts';
import { DefineErrors, field, num, section } from './define-errors.ts';

/** the planner "auto" (docs/planners.md): not a registered planner, so not in GET /planners */
const AUTO_PLANNER = {
  name: 'auto',
  summary: 'auto: plans with every planner that supports the mission (time limit shared) and keeps the best by the objective, among those within 0.5 PoC points of the best',
  schema: { params: [] },
};

interface Planner {
  name: string;
  summary: string;
  schema: PlannerSchema;
}
class DefinePanel {
  private doc: MissionDoc = newDraft('New mission', 1);
  /** the document last given to app.update by this tab (to tell our own updates from others) */
  private pushed: MissionDoc | null = null;
  private savedJson: string | null = null;
  /** the document as it was loaded (opened, new or imported): what "unsaved changes" compares with */
  private baseJson = '';
  private undoStack: MissionDoc[] = [];

  private cameras: CatalogCamera[] = [];
  private planners: Planner[] = [];

  // controls
  private nameInput!: HTMLInputElement;
  private status!: HTMLElement;
  private saveBtn!: HTMLButtonElement;
  private errors: DefineErrors;
  private camera!: CameraSection;
  private uavs!: DefineUavs;
  private map!: DefineMap;
  // the pattern (docs/patterns.md): area or corridor, the corridor's line and width, the options
  private patternSelect!: HTMLSelectElement;
  private widthInput!: HTMLInputElement;
  private corridorRow!: HTMLElement;
  private corridorInfo!: HTMLElement;
  private patternInputs: Partial<Record<keyof PatternOptions, HTMLInputElement | HTMLSelectElement>> = {};
  private structureRow!: HTMLElement;
  private structureControls!: StructureControls;
  private obliqueControls!: ObliqueControls;
  private windControls!: WindControls;
  private terrainControls!: TerrainControls;
  private fieldControls!: FieldControls;
  private objectiveControl!: ObjectiveControl;
  private readonly host: ExtrasHost = {
    doc: () => this.doc,
    commit: (d) => {
      this.commit(d);
      this.refreshForm();
    },
    placeRally: () => this.uavs.placeRally(),
  };
  private modeSelect!: HTMLSelectElement;
  private plannerSelect!: HTMLSelectElement;
  private plannerSummary!: HTMLElement;
  private paramsBox!: HTMLElement;
  private seedInput!: HTMLInputElement;

  constructor(
    private panel: HTMLElement,
    private app: App,
  ) {
    this.baseJson = JSON.stringify(this.doc);
    this.errors = new DefineErrors(panel, { doc: () => this.doc, overlap: () => this.camera.overlap() });
    this.build();
    app.subscribe((s) => {
      if (s.mission !== this.pushed) this.load(s.mission);
      else this.showStatus();
    });
    void this.loadCatalogs();
    window.addEventListener('uavcover:catalog-changed', () => void this.loadCatalogs());
  }

  // ---------------------------------------------------------------- layout

  private build(): void {
    const p = this.panel;
    p.classList.add('define-panel');

    const head = el('div', { class: 'define-head' });
    this.nameInput = el('input', { type: 'text', 'data-testid': 'mission-name', 'aria-label': 'Mission name', maxlength: '256', placeholder: 'Mission name' });
    this.nameInput.addEventListener('change', () => this.commit({ ...this.doc, name: this.nameInput.value.trim() || 'mission' }));
    this.saveBtn = el('button', { type: 'button', class: 'primary', 'data-testid': 'mission-save' }, 'Save');
    this.saveBtn.addEventListener('click', () => void this.save());
    const nameRow = el('div', { class: 'define-name', 'data-anchor': 'name' });
    nameRow.append(this.nameInput, this.saveBtn);
    this.status = el('div', { class: 'define-status muted', 'data-testid': 'mission-status', role: 'status', 'aria-live': 'polite' });
    head.append(nameRow, this.status, this.errors.general);
    p.appendChild(head);

    this.map = new DefineMap(this.app.map, p, {
      doc: () => this.doc,
      commit: (d) => this.commit(d),
      undo: () => this.undo(),
      flash: (text) => this.flash(text),
      corridorDrawn: (line) => {
        this.commit(withCorridor(this.doc, line, num(this.widthInput.value) ?? 100));
        this.renderPattern();
      },
      footprintDrawn: (polys) => {
        if (polys.length === 1) this.commit(withStructure(this.doc, { ...this.structureControls.values(), footprint: [polys[0][0]] }));
        this.renderPattern();
      },
      isPlacing: () => this.uavs.isPlacing(),
      place: (at) => this.uavs.place(at),
      stopPlacing: () => this.uavs.stopPlacing(),
      renderStarts: () => this.uavs.renderStarts(),
    });

    this.buildPattern();

    this.uavs = new DefineUavs(p, this.app.map, this.map.markers, {
      doc: () => this.doc,
      commit: (d) => this.commit(d),
      cameras: () => this.cameras,
      cancelModes: () => this.map.cancelModes(),
      say: (text) => (this.status.textContent = text),
      showStatus: () => this.showStatus(),
    }, this.host);

    this.camera = new CameraSection(p, {
      doc: () => this.doc,
      commit: (d) => this.commit(d),
      cameras: () => this.cameras,
      renderUavs: () => this.uavs.render(),
      errors: this.errors,
    });

    // planning
    const plan = section(this.panel, 'Planning');
    this.modeSelect = el('select', { 'data-testid': 'mode-select' });
    for (const [v, t] of [
      ['strict', 'Strict: paths stay inside the area'],
      ['coverage', 'Coverage: paths may leave the area slightly to cover its edges'],
    ])
      this.modeSelect.appendChild(el('option', { value: v }, t));
    this.modeSelect.addEventListener('change', () => this.commit({ ...this.doc, mode: this.modeSelect.value }));
    field(plan, 'Mode', 'mode', this.modeSelect);
    this.plannerSelect = el('select', { 'data-testid': 'planner-select' });
    this.plannerSelect.addEventListener('change', () => {
      const fields = fieldsFromSchema(this.planner(this.plannerSelect.value)?.schema);
      const old = (this.doc.planner_params as Record<string, unknown> | undefined) ?? {};
      const d: MissionDoc = { ...this.doc, planner: this.plannerSelect.value, planner_params: paramsForSchema(fields, old) };
      if (Object.keys(d.planner_params as object).length === 0) delete d.planner_params;
      this.commit(d);
      this.renderParams();
      this.objectiveControl.render(d);
    });
    field(plan, 'Planner', 'planner', this.plannerSelect);
    this.plannerSummary = el('p', { class: 'define-small muted' });
    plan.appendChild(this.plannerSummary);
    this.objectiveControl = new ObjectiveControl(this.host, plan);
    this.paramsBox = el('div', { class: 'define-params', 'data-testid': 'planner-params', 'data-anchor': 'planner_params' });
    plan.appendChild(this.paramsBox);
    this.windControls = new WindControls(this.host);
    plan.appendChild(this.windControls.row);
    // terrain (issue 31): a DEM uploaded to the server, or its tiles
    this.terrainControls = new TerrainControls({
      ...this.host,
      listDems: () => api.get<{ items: DemEntry[]; server_tiles: boolean }>('/dems'),
      uploadDem: (file: File) => {
        const form = new FormData();
        form.append('file', file, file.name);
        return api.postForm<DemEntry>('/dems', form);
      },
      say: (message: string, error = false) => {
        if (error) this.errors.showGeneral(message, 'terrain.dem_id');
        else this.status.textContent = message;
      },
    });
    plan.appendChild(this.terrainControls.row);
    this.fieldControls = new FieldControls(this.host);
    plan.appendChild(this.fieldControls.row);
    this.seedInput = el('input', { type: 'number', min: '0', step: '1', 'data-testid': 'seed-input' });
    this.seedInput.addEventListener('change', () => {
      const s = num(this.seedInput.value);
      const d = { ...this.doc };
      if (s === undefined) delete d.seed;
      else d.seed = s;
      this.commit(d);
    });
    field(plan, 'Seed', 'seed', this.seedInput);
  }

  /** the Pattern section: area or corridor (drawn as a polyline, with its width), and the options */
  private buildPattern(): void {
    const sec = section(this.panel, 'Pattern');
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
      if (k !== 'corridor' && this.doc.corridor !== undefined) this.commit(withCorridor(this.doc, null, 0));
      if (k !== 'structure' && this.doc.structure !== undefined) this.commit(withStructure(this.doc, null));
      this.renderPattern();
      this.map.render();
    });
    field(sec, 'Pattern', 'corridor structure', this.patternSelect);
    this.corridorRow = el('div', { class: 'define-corridor' });
    const tools = el('div', { class: 'define-tools' });
    tools.appendChild(
      this.map.drawButton('corridor', { 'data-testid': 'draw-corridor', title: 'Click the centre line’s vertices on the map; click the last one again to finish (Esc cancels)' }, 'Draw corridor line'),
    );
    this.corridorRow.appendChild(tools);
    this.widthInput = el('input', { type: 'number', min: '1', max: '5000', step: 'any', value: '100', 'data-testid': 'corridor-width' });
    this.widthInput.addEventListener('change', () => {
      const c = corridorOf(this.doc);
      const w = num(this.widthInput.value);
      if (c && w !== undefined) this.commit(withCorridor(this.doc, c.line, w));
      this.map.render();
    });
    field(this.corridorRow, 'Width', 'corridor.width_m', this.widthInput, 'm');
    this.corridorInfo = el('p', { class: 'define-small muted', 'data-testid': 'corridor-info' });
    this.corridorRow.appendChild(this.corridorInfo);
    sec.appendChild(this.corridorRow);
    // the structure: its footprint drawn as a polygon, its height, standoff, safe height and roof pass
    this.structureRow = el('div', { class: 'define-structure-row' });
    const stools = el('div', { class: 'define-tools' });
    stools.appendChild(
      this.map.drawButton('footprint', { 'data-testid': 'draw-footprint', title: 'Click the building’s corners on the map; click the first one again to close it (Esc cancels)' }, 'Draw footprint'),
    );
    this.structureControls = new StructureControls(this.host);
    this.structureRow.append(stools, this.structureControls.row);
    sec.appendChild(this.structureRow);
    // the options; a changed one writes the pattern block (defaults are left out)
    const opts = el('div', { class: 'define-pattern-options', 'data-testid': 'pattern-options' });
    const check = (key: keyof PatternOptions, label: string, title: string) => {
      const i = el('input', { type: 'checkbox', 'data-testid': `pattern-${key}`, title });
      i.addEventListener('change', () => this.commit(withPattern(this.doc, { [key]: i.checked })));
      field(opts, label, `pattern.${key}`, i);
      this.patternInputs[key] = i;
    };
    check('crosshatch', 'Crosshatch', 'sweep every part twice, the second time at 90° (double grid)');
    const ta = el('input', { type: 'number', min: '0', max: '500', step: 'any', placeholder: '0', 'data-testid': 'pattern-turnaround_m', title: 'legs extend beyond the area by this much, camera off' });
    ta.addEventListener('change', () => this.commit(withPattern(this.doc, { turnaround_m: num(ta.value) ?? 0 })));
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
    entry.addEventListener('change', () => this.commit(withPattern(this.doc, { entry: entry.value as PatternOptions['entry'] })));
    field(opts, 'Entry', 'pattern.entry', entry);
    this.patternInputs.entry = entry;
    check('alternate_transects', 'Alternate transects', 'every other lane, then back for the rest (fixed-wing turns)');
    check('capture_in_turnaround', 'Camera in turns', 'keep the camera on in turns and turnarounds');
    this.obliqueControls = new ObliqueControls(this.host);
    opts.appendChild(this.obliqueControls.row);
    sec.append(opts, el('p', { class: 'define-small muted' }, 'Corridors, obliques and the options need a lane planner (boustrophedon, or milp for corridors): see “uavcover planners”.'));
  }

  private renderPattern(): void {
    const c = corridorOf(this.doc);
    const st = structureOf(this.doc);
    const kind = c !== null ? 'corridor' : st !== null ? 'structure' : this.patternSelect.value;
    this.patternSelect.value = kind;
    const corridor = kind === 'corridor';
    this.corridorRow.hidden = !corridor;
    this.structureRow.hidden = kind !== 'structure';
    this.structureControls.render(this.doc);
    this.obliqueControls.render(this.doc);
    if (c) this.widthInput.value = String(c.width_m);
    this.corridorInfo.textContent = c
      ? `Centre line of ${c.line.length} vertices, ${c.width_m} m wide.`
      : 'No corridor yet: press “Draw corridor line” and click its vertices on the map.';
    const p = patternOf(this.doc) ?? PATTERN_DEFAULTS;
    for (const [k, i] of Object.entries(this.patternInputs) as [keyof PatternOptions, HTMLInputElement | HTMLSelectElement][]) {
      const v = p[k];
      if (i instanceof HTMLInputElement && i.type === 'checkbox') i.checked = v === true;
      else i.value = k === 'turnaround_m' && v === 0 ? '' : String(v);
    }
  }

  // ---------------------------------------------------------------- catalogs

  private async loadCatalogs(): Promise<void> {
    const fails: string[] = [];
    const get = async <T>(path: string): Promise<T[]> => {
      try {
        return (await api.get<{ items: T[] }>(path)).items;
      } catch (e) {
        fails.push(`${path}: ${errorText(e)}`);
        return [];
      }
    };
    let uavCatalog: CatalogUav[];
    [uavCatalog, this.cameras, this.planners] = await Promise.all([
      get<CatalogUav>('/uavs'),
      get<CatalogCamera>('/cameras'),
      get<Planner>('/planners'),
    ]);
    if (fails.length) this.errors.showGeneral(`Could not load the catalogs: ${fails.join('; ')}`);
    this.uavs.setCatalog(uavCatalog);
    this.plannerSelect.replaceChildren();
    if (this.planners.length) this.planners.push(AUTO_PLANNER);
    for (const pl of this.planners) this.plannerSelect.appendChild(el('option', { value: pl.name }, pl.name));
    this.refreshForm();
  }

  private planner(name: string): Planner | undefined {
    return this.planners.find((p) => p.name === name);
  }

  // ---------------------------------------------------------------- state

  /** a mission document arrives from elsewhere (opened, imported, new) */
  private load(doc: MissionDoc | null): void {
    let d = doc ?? newDraft('New mission', 1);
    if (typeof d.uavs === 'number' && Number.isInteger(d.uavs) && d.uavs > 0 && d.uavs <= 200)
      d = { ...d, uavs: Array.from({ length: d.uavs as number }, (_, i) => ({ id: `uav${i + 1}` })) };
    this.pushed = doc; // the document as received: later updates of other fields do not load it again
    this.doc = d;
    this.undoStack = [];
    this.uavs.reset();
    this.savedJson = this.app.state.missionId !== null ? JSON.stringify(d) : null;
    this.baseJson = JSON.stringify(d);
    this.map.cancelModes();
    this.errors.clear();
    this.errors.clearGeneral();
    if (d !== doc || this.app.state.dirty !== false) this.push(d);
    this.refreshForm();
    this.map.render();
    this.camera.scheduleValidate(0);
  }

  private push(d: MissionDoc): void {
    this.pushed = d;
    // unsaved edits: the document differs from the saved revision, or from the draft as it arrived
    // (a new mission or an imported file that nobody has touched yet holds no work to lose)
    this.app.update({ mission: d, dirty: JSON.stringify(d) !== (this.savedJson ?? this.baseJson) });
  }

  /** the operator changed the document */
  private commit(d: MissionDoc, undoable = true): void {
    if (JSON.stringify(d) === JSON.stringify(this.doc)) return; // nothing changed (a change event repeated)
    if (undoable) {
      this.undoStack.push(this.doc);
      if (this.undoStack.length > 200) this.undoStack.shift();
    }
    this.doc = d;
    this.push(d);
    this.camera.scheduleValidate();
  }

  private undo(): void {
    const prev = this.undoStack.pop();
    if (!prev) {
      this.flash('Nothing to undo.');
      return;
    }
    this.doc = prev;
    this.push(prev);
    this.refreshForm();
    this.map.render();
    this.camera.scheduleValidate();
  }

  private showStatus(): void {
    const s = this.app.state;
    const dirty = this.savedJson === null || JSON.stringify(this.doc) !== this.savedJson;
    let text: string;
    if (s.missionId === null) text = 'New mission, not saved yet.';
    else text = `Mission #${s.missionId}, revision ${s.revision}${dirty ? ' — unsaved changes' : ' — saved'}`;
    this.status.textContent = text;
    this.status.classList.toggle('define-dirty', dirty);
    this.saveBtn.textContent = s.missionId === null ? 'Save' : dirty ? 'Save revision' : 'Saved';
  }

  private flash(text: string): void {
    this.status.textContent = text;
    window.setTimeout(() => this.showStatus(), 2000);
  }

  // ---------------------------------------------------------------- form

  private refreshForm(): void {
    const d = this.doc;
    this.nameInput.value = typeof d.name === 'string' ? d.name : '';
    this.map.renderInfo();
    this.renderPattern();
    this.uavs.render();
    this.camera.render();
    this.modeSelect.value = d.mode === 'coverage' ? 'coverage' : 'strict';
    const planner = typeof d.planner === 'string' ? d.planner : 'darp';
    if (this.planners.length && !this.planner(planner)) this.plannerSelect.appendChild(el('option', { value: planner }, planner));
    this.plannerSelect.value = planner;
    this.renderParams();
    this.objectiveControl.render(d);
    this.windControls.render(d);
    this.terrainControls.render(d);
    this.fieldControls.render(d);
    this.uavs.sharesAuto.render(d);
    this.seedInput.value = typeof d.seed === 'number' ? String(d.seed) : '';
    this.seedInput.placeholder = '1';
    this.showStatus();
  }

  private renderParams(): void {
    const pl = this.planner(this.plannerSelect.value);
    this.plannerSummary.textContent = pl?.summary ?? '';
    const fields = fieldsFromSchema(pl?.schema);
    const values = (this.doc.planner_params as Record<string, unknown> | undefined) ?? {};
    renderSchemaForm(this.paramsBox, fields, values, (params, name, error) => {
      const d: MissionDoc = { ...this.doc, planner_params: params };
      if (Object.keys(params).length === 0) delete d.planner_params;
      this.commit(d);
      if (error) window.setTimeout(() => this.errors.show(`planner_params.${name}`, error), 0);
    });
  }

  // ---------------------------------------------------------------- save

  private async save(): Promise<void> {
    const s = this.app.state;
    this.saveBtn.disabled = true;
    this.errors.clearGeneral();
    const doc = this.doc;
    try {
      const r =
        s.missionId === null
          ? await api.post<{ id: number; revision: number }>('/missions', doc)
          : await api.put<{ id: number; revision: number }>(`/missions/${s.missionId}`, doc);
      this.savedJson = JSON.stringify(doc);
      this.pushed = doc;
      this.app.update({ missionId: r.id, revision: r.revision, mission: doc, dirty: false });
      this.errors.clear();
      this.status.textContent = `Saved: mission #${r.id}, revision ${r.revision}.`;
      this.saveBtn.textContent = 'Saved';
    } catch (e) {
      this.errors.clear();
      if (e instanceof ApiError && e.status === 422) {
        this.errors.show(e.field, e.message);
        this.status.textContent = 'Not saved: fix the field marked in red.';
      } else {
        this.errors.showGeneral(`Not saved: ${errorText(e)}`, e instanceof ApiError ? e.field : '');
        this.showStatus();
      }
    } finally {
      this.saveBtn.disabled = false;
    }
  }

  show(): void {
    if (this.app.state.mission === null) this.push(this.doc);
    this.map.show();
  }

  hide(): void {
    this.map.hide();
  }
}

export const defineTab: Tab = panelTab('define', 'Define', (panel, app) => new DefinePanel(panel, app));
