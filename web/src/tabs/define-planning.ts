// The Define tab's Planning section (issue 11): mode, planner (those of GET /planners, and "auto" with its
// objective) and its parameters' form, the wind, the terrain (issue 31: a DEM uploaded to the server, or
// its tiles), the flight software and field options, and the seed.
import { el } from '../dom.ts';
import { api } from '../api.ts';
import type { MissionDoc } from '../mission-doc.ts';
import { fieldsFromSchema, paramsForSchema, renderSchemaForm, type PlannerSchema } from '../schema-form.ts';
import { FieldControls, ObjectiveControl, TerrainControls, WindControls, type DemEntry, type ExtrasHost } from './define-extras.ts';
import { field, num, section, type DefineErrors } from './define-errors.ts';

/** the planner "auto" (docs/planners.md): not a registered planner, so not in GET /planners */
const AUTO_PLANNER = {
  name: 'auto',
  summary: 'auto: plans with every planner that supports the mission (time limit shared) and keeps the best by the objective, among those within 0.5 PoC points of the best',
  schema: { params: [] },
};

export interface Planner {
  name: string;
  summary: string;
  schema: PlannerSchema;
}

export interface PlanningHost {
  doc(): MissionDoc;
  commit(d: MissionDoc): void;
  errors: Pick<DefineErrors, 'show' | 'showGeneral'>;
  /** a note in the status line */
  say(text: string): void;
}

export class PlanningSection {
  private planners: Planner[] = [];
  private objectiveControl: ObjectiveControl;
  private windControls: WindControls;
  private terrainControls: TerrainControls;
  private fieldControls: FieldControls;
  private modeSelect: HTMLSelectElement;
  private plannerSelect: HTMLSelectElement;
  private plannerSummary: HTMLElement;
  private paramsBox: HTMLElement;
  private seedInput: HTMLInputElement;

  constructor(
    panel: HTMLElement,
    private host: PlanningHost,
    /** the host of define-extras' controls (its commit draws the whole form again) */
    extras: ExtrasHost,
  ) {
    const plan = section(panel, 'Planning');
    this.modeSelect = el('select', { 'data-testid': 'mode-select' });
    for (const [v, t] of [
      ['strict', 'Strict: paths stay inside the area'],
      ['coverage', 'Coverage: paths may leave the area slightly to cover its edges'],
    ])
      this.modeSelect.appendChild(el('option', { value: v }, t));
    this.modeSelect.addEventListener('change', () => this.host.commit({ ...this.host.doc(), mode: this.modeSelect.value }));
    field(plan, 'Mode', 'mode', this.modeSelect);
    this.plannerSelect = el('select', { 'data-testid': 'planner-select' });
    this.plannerSelect.addEventListener('change', () => {
      const fields = fieldsFromSchema(this.planner(this.plannerSelect.value)?.schema);
      const doc = this.host.doc();
      const old = (doc.planner_params as Record<string, unknown> | undefined) ?? {};
      const d: MissionDoc = { ...doc, planner: this.plannerSelect.value, planner_params: paramsForSchema(fields, old) };
      if (Object.keys(d.planner_params as object).length === 0) delete d.planner_params;
      this.host.commit(d);
      this.renderParams();
      this.objectiveControl.render(d);
    });
    field(plan, 'Planner', 'planner', this.plannerSelect);
    this.plannerSummary = el('p', { class: 'define-small muted' });
    plan.appendChild(this.plannerSummary);
    this.objectiveControl = new ObjectiveControl(extras, plan);
    this.paramsBox = el('div', { class: 'define-params', 'data-testid': 'planner-params', 'data-anchor': 'planner_params' });
    plan.appendChild(this.paramsBox);
    this.windControls = new WindControls(extras);
    plan.appendChild(this.windControls.row);
    // terrain (issue 31): a DEM uploaded to the server, or its tiles
    this.terrainControls = new TerrainControls({
      ...extras,
      listDems: () => api.get<{ items: DemEntry[]; server_tiles: boolean }>('/dems'),
      uploadDem: (file: File) => {
        const form = new FormData();
        form.append('file', file, file.name);
        return api.postForm<DemEntry>('/dems', form);
      },
      say: (message: string, error = false) => {
        if (error) this.host.errors.showGeneral(message, 'terrain.dem_id');
        else this.host.say(message);
      },
    });
    plan.appendChild(this.terrainControls.row);
    this.fieldControls = new FieldControls(extras);
    plan.appendChild(this.fieldControls.row);
    this.seedInput = el('input', { type: 'number', min: '0', step: '1', 'data-testid': 'seed-input' });
    this.seedInput.addEventListener('change', () => {
      const s = num(this.seedInput.value);
      const d = { ...this.host.doc() };
      if (s === undefined) delete d.seed;
      else d.seed = s;
      this.host.commit(d);
    });
    field(plan, 'Seed', 'seed', this.seedInput);
  }

  /** the planners of GET /planners (and "auto" beside them), into the select */
  setPlanners(list: Planner[]): void {
    this.planners = list;
    this.plannerSelect.replaceChildren();
    if (this.planners.length) this.planners.push(AUTO_PLANNER);
    for (const pl of this.planners) this.plannerSelect.appendChild(el('option', { value: pl.name }, pl.name));
  }

  private planner(name: string): Planner | undefined {
    return this.planners.find((p) => p.name === name);
  }

  /** the document's mode, planner, its parameters and options, and seed into the section */
  render(d: MissionDoc): void {
    this.modeSelect.value = d.mode === 'coverage' ? 'coverage' : 'strict';
    const planner = typeof d.planner === 'string' ? d.planner : 'darp';
    if (this.planners.length && !this.planner(planner)) this.plannerSelect.appendChild(el('option', { value: planner }, planner));
    this.plannerSelect.value = planner;
    this.renderParams();
    this.objectiveControl.render(d);
    this.windControls.render(d);
    this.terrainControls.render(d);
    this.fieldControls.render(d);
    this.seedInput.value = typeof d.seed === 'number' ? String(d.seed) : '';
    this.seedInput.placeholder = '1';
  }

  /** the planner's summary and its parameters' form */
  private renderParams(): void {
    const pl = this.planner(this.plannerSelect.value);
    this.plannerSummary.textContent = pl?.summary ?? '';
    const fields = fieldsFromSchema(pl?.schema);
    const values = (this.host.doc().planner_params as Record<string, unknown> | undefined) ?? {};
    renderSchemaForm(this.paramsBox, fields, values, (params, name, error) => {
      const d: MissionDoc = { ...this.host.doc(), planner_params: params };
      if (Object.keys(params).length === 0) delete d.planner_params;
      this.host.commit(d);
      if (error) window.setTimeout(() => this.host.errors.show(`planner_params.${name}`, error), 0);
    });
  }
}
