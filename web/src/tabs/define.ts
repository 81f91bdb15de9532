// The Define tab (issue 11): the mission document edited section by section, saved revision by revision.
// This file composes the parts and holds the document: every change goes through commit (undo stack,
// the app's state, the server's check), a document from elsewhere through load; the status line tells
// unsaved changes. The parts: the map (define-map.ts: area and no-fly zones), Pattern (define-pattern.ts),
// UAVs (define-uavs.ts: rows, shares, starts, rally points), camera and the server's check
// (define-camera.ts), Planning (define-planning.ts), the errors beside the fields (define-errors.ts) and
// the mission options (define-extras.ts). The state's mission document is always what the operator sees.
import { el } from '../dom.ts';
// first: geoman and its CSS come before the tab's own CSS
import { DefineMap } from './define-map.ts';
import { api, ApiError } from '../api.ts';
import { panelTab, type App, type Tab } from '../state.ts';
import { newDraft, type MissionDoc } from '../mission-doc.ts';
import '../missions.css';
import '../define.css';
import { errorText } from './missions.ts';
import type { ExtrasHost } from './define-extras.ts';
import { CameraSection, type CatalogCamera } from './define-camera.ts';
import { DefineUavs, type CatalogUav } from './define-uavs.ts';
import { PatternSection } from './define-pattern.ts';
import { PlanningSection, type Planner } from './define-planning.ts';
import { DefineErrors } from './define-errors.ts';

class DefinePanel {
  private doc: MissionDoc = newDraft('New mission', 1);
  /** the document last given to app.update by this tab (to tell our own updates from others) */
  private pushed: MissionDoc | null = null;
  private savedJson: string | null = null;
  /** the document as it was loaded (opened, new or imported): what "unsaved changes" compares with */
  private baseJson = '';
  private undoStack: MissionDoc[] = [];
  private cameras: CatalogCamera[] = [];

  private nameInput!: HTMLInputElement;
  private status!: HTMLElement;
  private saveBtn!: HTMLButtonElement;
  // the parts, in the panel's order
  private errors: DefineErrors;
  private map!: DefineMap;
  private pattern!: PatternSection;
  private uavs!: DefineUavs;
  private camera!: CameraSection;
  private planning!: PlanningSection;
  /** what define-extras' controls see: their commit draws the whole form again */
  private readonly host: ExtrasHost = {
    doc: () => this.doc,
    commit: (d) => {
      this.commit(d);
      this.refreshForm();
    },
    placeRally: () => this.uavs.placeRally(),
  };

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

    this.uavs = new DefineUavs(
      p,
      this.app.map,
      this.map.markers,
      {
        doc: () => this.doc,
        commit: (d) => this.commit(d),
        cameras: () => this.cameras,
        cancelModes: () => this.map.cancelModes(),
        say: (text) => (this.status.textContent = text),
        showStatus: () => this.showStatus(),
      },
      this.host,
    );

    this.camera = new CameraSection(p, {
      doc: () => this.doc,
      commit: (d) => this.commit(d),
      cameras: () => this.cameras,
      renderUavs: () => this.uavs.render(),
      errors: this.errors,
    });

    this.planning = new PlanningSection(
      p,
      {
        doc: () => this.doc,
        commit: (d) => this.commit(d),
        errors: this.errors,
        say: (text) => (this.status.textContent = text),
      },
      this.host,
    );
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
    let uavCatalog: CatalogUav[], planners: Planner[];
    [uavCatalog, this.cameras, planners] = await Promise.all([
      get<CatalogUav>('/uavs'),
      get<CatalogCamera>('/cameras'),
      get<Planner>('/planners'),
    ]);
    if (fails.length) this.errors.showGeneral(`Could not load the catalogs: ${fails.join('; ')}`);
    this.uavs.setCatalog(uavCatalog);
    this.planning.setPlanners(planners);
    this.refreshForm();
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
    this.planning.render(d);
    this.uavs.sharesAuto.render(d);
    this.showStatus();
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
