// The catalog editor (issue 29): the UAVs and cameras of the server's catalogs (docs/api.md
// "Catalogs": /uavs and /cameras, POST, PUT, DELETE) added, edited and deleted from the Missions tab.
// A server refusal shows next to the field it names. Other tabs learn of a change through the window
// event `uavcover:catalog-changed` (the Define tab reloads its catalog lists).
import { api, ApiError } from './api.ts';
import { el } from './job-ui.ts';

type Kind = 'uavs' | 'cameras';
type Entry = Record<string, unknown> & { id: number; name: string };

interface Field {
  key: string;
  label: string;
  unit?: string;
  step?: string;
  kind?: 'text' | 'camera';
}

const FIELDS: Record<Kind, Field[]> = {
  uavs: [
    { key: 'name', label: 'Name', kind: 'text' },
    { key: 'speed_mps', label: 'Speed', unit: 'm/s', step: 'any' },
    { key: 'max_accel_mps2', label: 'Acceleration', unit: 'm/s²', step: 'any' },
    { key: 'endurance_min', label: 'Endurance', unit: 'min', step: 'any' },
    { key: 'cost_per_min_eur', label: 'Cost', unit: '€/min', step: 'any' },
    { key: 'camera_id', label: 'Camera', kind: 'camera' },
  ],
  cameras: [
    { key: 'name', label: 'Name', kind: 'text' },
    { key: 'sensor_width_mm', label: 'Sensor width', unit: 'mm', step: 'any' },
    { key: 'focal_length_mm', label: 'Focal length', unit: 'mm', step: 'any' },
    { key: 'image_width_px', label: 'Image width', unit: 'px', step: '1' },
    { key: 'hfov_deg', label: 'HFOV', unit: '°', step: 'any' },
  ],
};

const DEFAULTS: Record<Kind, Record<string, unknown>> = {
  uavs: { name: '', speed_mps: 10, max_accel_mps2: 3, endurance_min: 25, cost_per_min_eur: 0.017228 },
  cameras: { name: '', sensor_width_mm: 13.2, focal_length_mm: 8.8, image_width_px: 5472, hfov_deg: 73.7 },
};

const TITLE: Record<Kind, string> = { uavs: 'UAVs', cameras: 'Cameras' };

function summary(kind: Kind, e: Entry, cameras: Entry[]): string {
  if (kind === 'uavs') {
    const cam = typeof e.camera_id === 'number' ? cameras.find((c) => c.id === e.camera_id)?.name ?? `camera #${e.camera_id}` : null;
    return `${e.speed_mps} m/s · ${e.endurance_min} min · ${e.cost_per_min_eur} €/min${cam ? ` · ${cam}` : ''}`;
  }
  return `${e.sensor_width_mm} mm sensor · ${e.focal_length_mm} mm lens · ${e.image_width_px} px · ${e.hfov_deg}°`;
}

export function catalogEditor(): HTMLElement {
  const box = el('details', { class: 'catalog-section', 'data-testid': 'catalog-section' });
  box.append(el('summary', {}, 'Catalog: UAVs and cameras'));
  const status = el('div', { class: 'missions-status', 'data-testid': 'catalog-status', role: 'status' });
  const lists: Record<Kind, HTMLElement> = {
    uavs: el('div', { class: 'catalog-list', 'data-testid': 'catalog-uavs' }),
    cameras: el('div', { class: 'catalog-list', 'data-testid': 'catalog-cameras' }),
  };
  const entries: Record<Kind, Entry[]> = { uavs: [], cameras: [] };
  for (const kind of ['uavs', 'cameras'] as Kind[]) {
    const head = el('div', { class: 'catalog-head' });
    const add = el('button', { type: 'button', 'data-testid': 'catalog-add', 'data-kind': kind }, kind === 'uavs' ? 'Add a UAV' : 'Add a camera');
    add.addEventListener('click', () => openForm(kind, null, lists[kind]));
    head.append(el('h4', {}, TITLE[kind]), add);
    box.append(head, lists[kind]);
  }
  box.append(status);

  const say = (text: string, error = false) => {
    status.textContent = text;
    status.classList.toggle('error', error);
  };
  const changed = () => window.dispatchEvent(new CustomEvent('uavcover:catalog-changed'));

  const load = async () => {
    try {
      const [u, c] = await Promise.all([api.get<{ items: Entry[] }>('/uavs'), api.get<{ items: Entry[] }>('/cameras')]);
      entries.uavs = u.items;
      entries.cameras = c.items;
      render();
    } catch (e) {
      say(`The catalogs cannot be read: ${(e as Error).message}`, true);
    }
  };

  const render = () => {
    for (const kind of ['uavs', 'cameras'] as Kind[]) {
      const list = lists[kind];
      list.replaceChildren();
      if (!entries[kind].length) list.append(el('p', { class: 'muted' }, 'none yet'));
      for (const e of entries[kind]) {
        const item = el('div', { class: 'catalog-item', 'data-testid': 'catalog-item', 'data-kind': kind, 'data-id': String(e.id) });
        const text = el('div', { class: 'catalog-text' });
        text.append(el('strong', {}, e.name), el('span', { class: 'muted catalog-summary' }, summary(kind, e, entries.cameras)));
        const actions = el('div', { class: 'catalog-actions' });
        const edit = el('button', { type: 'button', 'data-testid': 'catalog-edit' }, 'Edit');
        edit.addEventListener('click', () => openForm(kind, e, item));
        const del = el('button', { type: 'button', class: 'danger', 'data-testid': 'catalog-delete' }, 'Delete');
        del.addEventListener('click', () => confirmDelete(kind, e, item));
        actions.append(edit, del);
        item.append(text, actions);
        list.append(item);
      }
    }
  };

  const confirmDelete = (kind: Kind, e: Entry, item: HTMLElement) => {
    item.querySelector('.mission-confirm')?.remove();
    const c = el('div', { class: 'mission-confirm', role: 'alertdialog' });
    const yes = el('button', { type: 'button', class: 'danger', 'data-testid': 'catalog-delete-confirm' }, 'Delete');
    const no = el('button', { type: 'button' }, 'Keep');
    c.append(el('span', {}, `Delete “${e.name}” from the catalog? Missions that name it by catalog_id will be refused until they name another.`), yes, no);
    no.addEventListener('click', () => c.remove());
    yes.addEventListener('click', async () => {
      try {
        await api.del(`/${kind}/${e.id}`);
        say(`Deleted “${e.name}”.`);
        await load();
        changed();
      } catch (err) {
        say(`“${e.name}” was not deleted: ${(err as Error).message}`, true);
      }
    });
    item.append(c);
  };

  const openForm = (kind: Kind, e: Entry | null, where: HTMLElement) => {
    box.querySelector('[data-testid=catalog-form]')?.remove();
    const form = el('form', { class: 'catalog-form', 'data-testid': 'catalog-form', 'data-kind': kind });
    form.noValidate = true; // the server's checks, in words next to the field, not the browser's bubbles
    const inputs = new Map<string, HTMLInputElement | HTMLSelectElement>();
    const values = e ?? DEFAULTS[kind];
    for (const f of FIELDS[kind]) {
      const row = el('label', { class: 'catalog-field' });
      row.append(el('span', { class: 'catalog-label' }, f.label));
      let input: HTMLInputElement | HTMLSelectElement;
      if (f.kind === 'camera') {
        const sel = el('select', { 'data-testid': 'catalog-input', 'data-field': f.key });
        sel.append(el('option', { value: '' }, 'none'));
        for (const c of entries.cameras) sel.append(el('option', { value: String(c.id) }, c.name));
        sel.value = typeof values.camera_id === 'number' ? String(values.camera_id) : '';
        input = sel;
      } else {
        input = el('input', {
          type: f.kind === 'text' ? 'text' : 'number',
          'data-testid': 'catalog-input',
          'data-field': f.key,
          ...(f.step ? { step: f.step } : {}),
          ...(f.kind === 'text' ? { maxlength: '200' } : {}),
        });
        const v = values[f.key];
        input.value = v === undefined || v === null ? '' : String(v);
      }
      input.setAttribute('aria-label', f.label);
      row.append(input);
      if (f.unit) row.append(el('span', { class: 'define-unit' }, f.unit));
      inputs.set(f.key, input);
      form.append(row);
    }
    const save = el('button', { type: 'submit', class: 'primary', 'data-testid': 'catalog-save' }, e ? 'Save' : 'Add');
    const cancel = el('button', { type: 'button', 'data-testid': 'catalog-cancel' }, 'Cancel');
    const buttons = el('div', { class: 'catalog-actions' });
    buttons.append(save, cancel);
    form.append(buttons);
    cancel.addEventListener('click', () => form.remove());
    form.addEventListener('keydown', (ev) => {
      if (ev.key === 'Escape') form.remove();
    });
    form.addEventListener('submit', async (ev) => {
      ev.preventDefault();
      form.querySelectorAll('[data-testid=catalog-error]').forEach((x) => x.remove());
      const body: Record<string, unknown> = {};
      for (const f of FIELDS[kind]) {
        const v = inputs.get(f.key)!.value.trim();
        if (f.kind === 'text') body[f.key] = v;
        else if (f.kind === 'camera') {
          if (v) body[f.key] = Number(v);
        } else if (v !== '') body[f.key] = Number(v);
      }
      save.disabled = true;
      try {
        if (e) await api.put(`/${kind}/${e.id}`, body);
        else await api.post(`/${kind}`, body);
        say(`${e ? 'Saved' : 'Added'} “${String(body.name)}”.`);
        form.remove();
        await load();
        changed();
      } catch (err) {
        const field = err instanceof ApiError ? err.field : '';
        const label = FIELDS[kind].find((f) => f.key === field)?.label;
        const msg = el('div', { class: 'define-field-error', 'data-testid': 'catalog-error', 'data-field': field, role: 'alert', title: field }, `${label ? `${label}: ` : ''}${(err as Error).message.replace(field ? `${field}: ` : '\u0000', '')}`);
        const input = inputs.get(field);
        if (input) input.closest('label')!.after(msg);
        else buttons.before(msg);
      } finally {
        save.disabled = false;
      }
    });
    where.after(form);
    inputs.get('name')!.focus();
  };

  box.addEventListener('toggle', () => {
    if (box.open) void load();
  });
  return box;
}
