// The Missions tab (issue 11): list, search and open stored missions with their extent on the map;
// duplicate, rename, delete, export; import a file by drag and drop (or a file picker); new mission.
import L from 'leaflet';
import { api, ApiError } from '../api.ts';
import { el } from '../dom.ts';
import { confirmDiscard } from '../discard.ts';
import { catalogEditor } from '../catalog-editor.ts';
import { panelTab, type App, type Tab } from '../state.ts';
import { docBbox, editableDoc, fieldLabel, fileName, humanMessage, newDraft, type MissionDoc } from '../mission-doc.ts';
import { readImport } from '../import.ts';
import '../missions.css';

/** files only the server's importer reads (zipped Shapefile, KMZ, KML, GeoPackage, DXF) */
const VECTOR_EXTENSIONS = new Set(['zip', 'kmz', 'kml', 'gpkg', 'dxf']);

interface MissionSummary {
  id: number;
  name: string;
  revision: number;
  created: string;
  updated: string;
  bbox: [number, number, number, number] | null;
}

interface Mission extends MissionSummary {
  latest_revision: number;
  mission: MissionDoc;
  source: unknown;
}

const PAGE = 20;

/** a server error in words */
export function errorText(e: unknown): string {
  if (e instanceof ApiError) {
    if (e.status === 409) return `Refused: ${e.message}`;
    // the field as the form names it ("Area, polygon 1"), not the document's path
    const label = fieldLabel(e.field);
    const msg = humanMessage(e.field, e.message);
    return label ? `${label}: ${msg}` : msg;
  }
  return e instanceof Error ? e.message : String(e);
}

function bboxBounds(b: [number, number, number, number] | null | undefined): L.LatLngBounds | null {
  if (!b || b.length !== 4 || !b.every(Number.isFinite)) return null;
  return L.latLngBounds([b[1], b[0]], [b[3], b[2]]);
}

function when(iso: string): string {
  const d = new Date(iso);
  return Number.isNaN(d.getTime()) ? iso : d.toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' });
}

/** download text as a file */
export function download(name: string, text: string, type = 'application/json'): void {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = el('a', { href: url, download: name });
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

class MissionsPanel {
  private list!: HTMLUListElement;
  private status!: HTMLElement;
  private search!: HTMLInputElement;
  private pager!: HTMLElement;
  private cursors: (number | null)[] = [null];
  private page = 0;
  private nextCursor: number | null = null;
  private items: MissionSummary[] = [];
  private selected: number | null = null;
  private extents = L.featureGroup();
  private hoverRect: L.Rectangle | null = null;
  private searchTimer = 0;
  private loadSeq = 0;

  constructor(
    private panel: HTMLElement,
    private app: App,
  ) {
    this.build();
    this.installDrop(panel);
    this.installDrop(app.map.getContainer());
  }

  private build(): void {
    const p = this.panel;
    p.classList.add('missions-panel');
    const bar = el('div', { class: 'missions-bar' });
    this.search = el('input', {
      type: 'search',
      placeholder: 'Search missions by name',
      'data-testid': 'mission-search',
      'aria-label': 'Search missions by name',
    });
    this.search.addEventListener('input', () => {
      clearTimeout(this.searchTimer);
      this.searchTimer = window.setTimeout(() => this.reload(), 250);
    });
    const newBtn = el('button', { type: 'button', class: 'primary', 'data-testid': 'mission-new' }, 'New mission');
    newBtn.addEventListener('click', async () => {
      if (!(await confirmDiscard(this.app, 'Start a new mission'))) return;
      this.app.update({ missionId: null, revision: null, mission: newDraft('New mission', 1), planId: null, dirty: true });
      this.app.showTab('define');
    });
    bar.append(this.search, newBtn);

    const drop = el('label', { class: 'missions-drop', title: 'uavcover mission, mCPP-optimized-DARP JSON, GeoJSON, KML/KMZ, zipped Shapefile, GeoPackage or DXF' });
    const input = el('input', {
      type: 'file',
      accept: '.json,.geojson,.kml,.kmz,.zip,.gpkg,.dxf,application/json,application/geo+json,application/vnd.google-earth.kml+xml',
      'data-testid': 'mission-import-input',
    });
    input.addEventListener('change', () => {
      const f = input.files?.[0];
      if (f) void this.importFile(f);
      input.value = '';
    });
    drop.append(
      input,
      el('strong', {}, 'Import a file'),
      el('span', { class: 'muted' }, ' — drop it here or on the map, or click to choose: uavcover mission, mCPP-optimized-DARP JSON, GeoJSON, KML'),
    );

    this.status = el('div', { class: 'missions-status', role: 'status', 'aria-live': 'polite' });
    this.list = el('ul', { class: 'missions-list', 'data-testid': 'mission-list' });
    this.pager = el('div', { class: 'missions-pager' });
    p.append(bar, drop, this.status, this.list, this.pager, catalogEditor());
  }

  show(): void {
    this.extents.addTo(this.app.map);
    void this.reload(true);
  }

  hide(): void {
    this.extents.remove();
    this.clearHover();
  }

  private say(text: string, error = false): void {
    this.status.textContent = text;
    this.status.classList.toggle('error', error);
  }

  /** reload the list; `keepPage` stays on the current page (after a change) */
  async reload(keepPage = false): Promise<void> {
    if (!keepPage) {
      this.cursors = [null];
      this.page = 0;
    }
    const seq = ++this.loadSeq;
    const q = new URLSearchParams({ limit: String(PAGE) });
    const name = this.search.value.trim();
    if (name) q.set('name', name);
    const cursor = this.cursors[this.page];
    if (cursor !== null && cursor !== undefined) q.set('cursor', String(cursor));
    try {
      const r = await api.get<{ items: MissionSummary[]; next_cursor: number | null }>(`/missions?${q}`);
      if (seq !== this.loadSeq) return;
      this.items = r.items;
      this.nextCursor = r.next_cursor;
      this.render();
      // nothing open yet: show where the listed missions are
      if (this.app.state.mission === null && this.extents.getLayers().length > 0)
        this.app.map.fitBounds(this.extents.getBounds(), { padding: [30, 30], maxZoom: 17 });
      if (this.status.classList.contains('error') === false) this.say('');
    } catch (e) {
      if (seq === this.loadSeq) this.say(errorText(e), true);
    }
  }

  private render(): void {
    this.list.replaceChildren();
    this.extents.clearLayers();
    if (this.items.length === 0) {
      const empty = el('li', { class: 'muted missions-empty' });
      empty.textContent = this.search.value.trim()
        ? `No mission matches “${this.search.value.trim()}”.`
        : 'No missions yet: create one or import a file.';
      this.list.appendChild(empty);
    }
    for (const m of this.items) this.list.appendChild(this.item(m));
    // the extents of the listed missions, faint; the selected one stands out
    for (const m of this.items) {
      const b = bboxBounds(m.bbox);
      if (!b) continue;
      const sel = m.id === this.selected;
      L.rectangle(b, {
        color: sel ? '#0072b2' : '#6b7785',
        weight: sel ? 2.5 : 1,
        dashArray: sel ? undefined : '4 4',
        fillOpacity: sel ? 0.08 : 0.02,
        interactive: true,
      })
        .bindTooltip(m.name)
        .on('click', () => this.select(m.id, true))
        .addTo(this.extents);
    }
    this.pager.replaceChildren();
    if (this.page > 0 || this.nextCursor !== null) {
      const prev = el('button', { type: 'button' }, '‹ Previous');
      prev.disabled = this.page === 0;
      prev.addEventListener('click', () => {
        this.page--;
        void this.reload(true);
      });
      const next = el('button', { type: 'button' }, 'Next ›');
      next.disabled = this.nextCursor === null;
      next.addEventListener('click', () => {
        this.cursors[this.page + 1] = this.nextCursor;
        this.page++;
        void this.reload(true);
      });
      this.pager.append(prev, el('span', { class: 'muted' }, `page ${this.page + 1}`), next);
    }
  }

  private item(m: MissionSummary): HTMLLIElement {
    const li = el('li', {
      class: 'mission-item',
      'data-testid': 'mission-item',
      'data-id': String(m.id),
      tabindex: '0',
    });
    if (m.id === this.selected) li.classList.add('selected');
    if (m.id === this.app.state.missionId) li.classList.add('open');
    const head = el('div', { class: 'mission-head' });
    const title = el('button', { type: 'button', class: 'mission-title', 'data-testid': 'mission-open', title: 'Open in the Define tab' }, m.name);
    title.addEventListener('click', (e) => {
      e.stopPropagation();
      void this.open(m.id);
    });
    head.append(title, el('span', { class: 'muted mission-meta' }, `#${m.id} · rev ${m.revision} · ${when(m.updated)}`));
    const actions = el('div', { class: 'mission-actions' });
    const act = (label: string, testid: string, fn: () => void, cls = '') => {
      const b = el('button', { type: 'button', 'data-testid': testid, class: cls }, label);
      b.addEventListener('click', (e) => {
        e.stopPropagation();
        fn();
      });
      actions.appendChild(b);
    };
    act('Open', 'mission-open-button', () => void this.open(m.id));
    act('Duplicate', 'mission-duplicate', () => void this.duplicate(m));
    act('Rename', 'mission-rename', () => this.startRename(li, m));
    act('Export', 'mission-export', () => void this.exportMission(m));
    act('Delete', 'mission-delete', () => this.confirmDelete(li, m), 'danger');
    li.append(head, actions);
    li.addEventListener('mouseenter', () => this.hover(m));
    li.addEventListener('mouseleave', () => this.clearHover());
    li.addEventListener('click', () => void this.open(m.id));
    li.addEventListener('keydown', (e) => {
      if (e.key === 'Enter' && e.target === li) void this.open(m.id);
    });
    return li;
  }

  private hover(m: MissionSummary): void {
    this.clearHover();
    const b = bboxBounds(m.bbox);
    if (!b) return;
    this.hoverRect = L.rectangle(b, { color: '#e69f00', weight: 2.5, fillOpacity: 0.1, interactive: false }).addTo(this.app.map);
  }

  private clearHover(): void {
    this.hoverRect?.remove();
    this.hoverRect = null;
  }

  private select(id: number, fit: boolean): void {
    this.selected = id;
    for (const li of this.list.querySelectorAll<HTMLElement>('.mission-item'))
      li.classList.toggle('selected', li.dataset.id === String(id));
    const m = this.items.find((x) => x.id === id);
    this.render();
    const b = bboxBounds(m?.bbox);
    if (fit && b) this.app.map.fitBounds(b, { padding: [30, 30], maxZoom: 18 });
  }

  private async fetchMission(id: number): Promise<Mission> {
    return api.get<Mission>(`/missions/${id}`);
  }

  async open(id: number, confirmed = false): Promise<void> {
    if (!confirmed && !(await confirmDiscard(this.app, `Open mission #${id}`))) return;
    this.say('Opening…');
    try {
      const m = await this.fetchMission(id);
      this.app.update({ missionId: m.id, revision: m.revision, mission: editableDoc(m), planId: null, dirty: false });
      const b = bboxBounds(m.bbox) ?? bboxBounds(docBbox(m.mission));
      if (b) this.app.map.fitBounds(b, { padding: [30, 30], maxZoom: 18 });
      this.say('');
      this.app.showTab('define');
    } catch (e) {
      this.say(`Could not open mission ${id}: ${errorText(e)}`, true);
    }
  }

  private async duplicate(m: MissionSummary): Promise<void> {
    try {
      const full = await this.fetchMission(m.id);
      const doc = { ...editableDoc(full), name: `${full.name} (copy)` };
      const r = await api.post<{ id: number; revision: number }>('/missions', doc);
      this.selected = r.id;
      await this.reload(true);
      this.say(`Duplicated as “${doc.name}” (#${r.id}).`);
    } catch (e) {
      this.say(`Could not duplicate “${m.name}”: ${errorText(e)}`, true);
    }
  }

  private startRename(li: HTMLElement, m: MissionSummary): void {
    const form = el('form', { class: 'mission-rename-form' });
    const input = el('input', { type: 'text', value: m.name, 'data-testid': 'mission-rename-input', 'aria-label': 'New name', maxlength: '256' });
    const ok = el('button', { type: 'submit', class: 'primary', 'data-testid': 'mission-rename-save' }, 'Save');
    const cancel = el('button', { type: 'button' }, 'Cancel');
    form.append(input, ok, cancel);
    li.querySelector('.mission-actions')?.replaceWith(form);
    input.focus();
    input.select();
    const done = () => this.render();
    cancel.addEventListener('click', (e) => {
      e.stopPropagation();
      done();
    });
    form.addEventListener('click', (e) => e.stopPropagation());
    input.addEventListener('keydown', (e) => {
      if (e.key === 'Escape') done();
    });
    form.addEventListener('submit', (e) => {
      e.preventDefault();
      void this.rename(m, input.value.trim());
    });
  }

  private async rename(m: MissionSummary, name: string): Promise<void> {
    if (!name) {
      this.say('A mission needs a name.', true);
      return;
    }
    try {
      const full = await this.fetchMission(m.id);
      const doc = { ...editableDoc(full), name };
      const r = await api.put<{ id: number; revision: number }>(`/missions/${m.id}`, doc);
      if (this.app.state.missionId === m.id) this.app.update({ revision: r.revision, mission: { ...(this.app.state.mission ?? doc), name }, dirty: false });
      await this.reload(true);
      this.say(`Renamed to “${name}” (revision ${r.revision}).`);
    } catch (e) {
      this.say(`Could not rename “${m.name}”: ${errorText(e)}`, true);
      this.render();
    }
  }

  private confirmDelete(li: HTMLElement, m: MissionSummary): void {
    const box = el('div', { class: 'mission-confirm', role: 'alertdialog' });
    const yes = el('button', { type: 'button', class: 'danger', 'data-testid': 'mission-delete-confirm' }, 'Delete');
    const no = el('button', { type: 'button' }, 'Keep');
    box.append(el('span', {}, `Delete “${m.name}” and its revisions?`), yes, no);
    li.querySelector('.mission-actions')?.replaceWith(box);
    box.addEventListener('click', (e) => e.stopPropagation());
    no.addEventListener('click', () => this.render());
    yes.addEventListener('click', () => void this.remove(m));
    yes.focus();
  }

  private async remove(m: MissionSummary): Promise<void> {
    try {
      await api.del(`/missions/${m.id}`);
      if (this.selected === m.id) this.selected = null;
      if (this.app.state.missionId === m.id) this.app.update({ missionId: null, revision: null, planId: null });
      await this.reload(true);
      this.say(`Deleted “${m.name}”.`);
    } catch (e) {
      // 409: the mission has queued or running jobs; the server's message says so
      this.say(`Could not delete “${m.name}”: ${e instanceof ApiError && e.status === 409 ? e.message : errorText(e)}`, true);
      this.render();
    }
  }

  private async exportMission(m: MissionSummary): Promise<void> {
    try {
      const full = await this.fetchMission(m.id);
      download(fileName(full.name), JSON.stringify(full.mission, null, 2) + '\n');
      this.say(`Exported ${fileName(full.name)}.`);
    } catch (e) {
      this.say(`Could not export “${m.name}”: ${errorText(e)}`, true);
    }
  }

  private installDrop(target: HTMLElement): void {
    target.addEventListener('dragover', (e) => {
      if (!e.dataTransfer || !Array.from(e.dataTransfer.types).includes('Files')) return;
      e.preventDefault();
      e.dataTransfer.dropEffect = 'copy';
      target.classList.add('missions-dragover');
    });
    target.addEventListener('dragleave', () => target.classList.remove('missions-dragover'));
    target.addEventListener('drop', (e) => {
      target.classList.remove('missions-dragover');
      const f = e.dataTransfer?.files?.[0];
      if (!f) return;
      e.preventDefault();
      void this.importFile(f);
    });
  }

  async importFile(f: File): Promise<void> {
    this.app.showTab('missions');
    if (f.size > 10 * 1024 * 1024) {
      this.say(`${f.name}: the file is larger than 10 MB.`, true);
      return;
    }
    if (!(await confirmDiscard(this.app, `Import ${f.name}`))) return;
    this.say(`Reading ${f.name}…`);
    try {
      // vector files go to the server's importer (GDAL: docs/import.md); a mission file is stored as it is
      const ext = f.name.toLowerCase().split('.').pop() ?? '';
      const r = VECTOR_EXTENSIONS.has(ext)
        ? null
        : readImport(await f.text(), f.name, (s) => new DOMParser().parseFromString(s, 'application/xml'));
      if (r && r.kind === 'mission') {
        const c = await api.post<{ id: number; revision: number }>('/missions', r.body);
        this.selected = c.id;
        this.search.value = '';
        await this.reload();
        this.say(`Imported ${f.name} as mission #${c.id}.`);
        await this.open(c.id, true);
      } else {
        const doc = await api.importFile<MissionDoc>(f, f.name);
        this.app.update({ missionId: null, revision: null, mission: doc, planId: null, dirty: true });
        const b = bboxBounds(docBbox(doc));
        if (b) this.app.map.fitBounds(b, { padding: [30, 30], maxZoom: 18 });
        this.say(`Read ${f.name}: a draft mission — check it and save it in the Define tab.`);
        this.app.showTab('define');
      }
    } catch (e) {
      this.say(`Could not import ${f.name}: ${errorText(e)}`, true);
    }
  }
}

export const missionsTab: Tab = panelTab('missions', 'Missions', (panel, app) => new MissionsPanel(panel, app));
