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
  newDraft,
  type MissionDoc,
} from '../mission-doc.ts';
import { fieldsFromSchema, paramsForSchema, renderSchemaForm, type PlannerSchema } from '../schema-form.ts';
import '../missions.css';
import '../define.css';
import { errorText } from './missions.ts';
import {
  FieldControls,
  ObjectiveControl,
  TerrainControls,
  WindControls,
  type DemEntry,
  type ExtrasHost,
} from './define-extras.ts';
import { CameraSection, type CatalogCamera } from './define-camera.ts';
import { DefineUavs, type CatalogUav } from './define-uavs.ts';
import { PatternSection } from './define-pattern.ts';
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
  private pattern!: PatternSection;
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
      corridorDrawn: (line) => this.pattern.corridorDrawn(line),
      footprintDrawn: (polys) => this.pattern.footprintDrawn(polys),
      isPlacing: () => this.uavs.isPlacing(),
      place: (at) => this.uavs.place(at),
      stopPlacing: () => this.uavs.stopPlacing(),
      renderStarts: () => this.uavs.renderStarts(),
    });

    this.pattern = new PatternSection(p, { doc: () => this.doc, commit: (d) => this.commit(d), map: this.map }, this.host);

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
    this.pattern.render();
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
