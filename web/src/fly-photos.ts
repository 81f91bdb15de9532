// The Fly tab's photos (issue 32, docs/photos.md): the operator picks the flight's photos; the app sends
// the head of each file (the tags come before the image data) to POST /photos/tags in batches, then the
// tags to POST /flights/{id}/photos, and draws what the photos saw (their footprints) and the gaps; the
// refly can start from those gaps (POST /flights/{id}/refly with the photos).
import L from 'leaflet';
import { api, ApiError } from './api.ts';
import { el } from './dom.ts';
import { HEAD_BYTES, photoBatches } from './fly-model.ts';

type PhotoTags = Record<string, unknown> & { name: string };
interface PhotoCoverage {
  photos: number;
  skipped: string[];
  poc: number;
  pooc: number;
  planned_poc: number;
  gaps_m2: number;
  geojson: GeoJSON.FeatureCollection;
}

export class FlyPhotos {
  readonly el = el('div', { class: 'fly-photos', 'data-testid': 'fly-photos' });
  private input = el('input', { type: 'file', multiple: '', accept: '.jpg,.jpeg,image/jpeg', 'data-testid': 'fly-photos-input', 'aria-label': 'The flight’s photos' });
  private takeoff = el('input', { type: 'number', step: 'any', placeholder: 'from the photos', 'data-testid': 'fly-photos-takeoff', title: 'the take-off’s height above sea level, for photos that carry a GPS altitude only (no DJI relative altitude)' });
  private message = el('div', { class: 'fly-message', 'data-testid': 'fly-photos-message', role: 'status' });
  private refly = el('button', { type: 'button', class: 'plan-small', 'data-testid': 'fly-photos-refly', disabled: '' }, 'Refly from the photos');
  private tags: PhotoTags[] = [];
  private layer = L.layerGroup();
  private renderer = L.canvas({ padding: 0.2 });

  constructor(
    private map: L.Map,
    private flightId: () => number | null,
  ) {
    const pick = el('label', { class: 'plan-row fly-photos-pick' });
    pick.append(el('span', {}, 'Photos'), this.input);
    const alt = el('label', { class: 'plan-row' });
    alt.append(el('span', {}, 'Take-off altitude'), this.takeoff, el('span', { class: 'define-unit' }, 'm a.s.l.'));
    const row = el('div', { class: 'plan-row' });
    row.append(this.refly);
    this.el.append(pick, alt, this.message, row);
    this.input.addEventListener('change', () => void this.read());
    // projected again a moment after the altitude is typed, not when the field loses focus: a blur from
    // clicking "Refly from the photos" would redraw the message under the pointer and eat the click
    let typed: number | undefined;
    this.takeoff.addEventListener('input', () => {
      clearTimeout(typed);
      typed = window.setTimeout(() => {
        if (this.tags.length) void this.cover();
      }, 500);
    });
    this.refly.addEventListener('click', () => void this.reflyFromPhotos());
  }

  /** the flight changed or the tab left: forget the photos and their drawing */
  clear(): void {
    this.tags = [];
    this.layer.remove();
    this.layer.clearLayers();
    this.refly.disabled = true;
    this.message.textContent = '';
    this.input.value = '';
  }

  private body(extra: Record<string, unknown> = {}): Record<string, unknown> {
    const b: Record<string, unknown> = { photos: this.tags, ...extra };
    const t = Number(this.takeoff.value);
    if (this.takeoff.value.trim() !== '' && Number.isFinite(t)) b.takeoff_alt_m = t;
    return b;
  }

  private fail(what: string, e: unknown): void {
    this.message.className = 'fly-message plan-error';
    this.message.textContent = `${what}: ${e instanceof ApiError ? e.message : String(e)}`;
  }

  private async read(): Promise<void> {
    const files = Array.from(this.input.files ?? []);
    if (files.length === 0) return;
    this.tags = []; // the photos' tags are kept once all are read (a typed altitude projects none before)
    this.refly.disabled = true;
    this.message.className = 'fly-message';
    const groups = photoBatches(files.map((f) => f.size));
    const tags: PhotoTags[] = [];
    try {
      for (const [k, group] of groups.entries()) {
        this.message.textContent = `Reading the photos’ tags… ${k + 1}/${groups.length}`;
        const form = new FormData();
        for (const i of group) form.append('photos', files[i].slice(0, HEAD_BYTES), files[i].name);
        const r = await api.postForm<{ items: PhotoTags[] }>('/photos/tags', form);
        tags.push(...r.items);
      }
    } catch (e) {
      this.fail('Photos', e);
      return;
    }
    this.tags = tags;
    await this.cover();
  }

  private async cover(): Promise<void> {
    const id = this.flightId();
    if (id === null) return;
    this.message.className = 'fly-message';
    this.message.textContent = `Projecting ${this.tags.length} photos…`;
    let c: PhotoCoverage;
    try {
      c = await api.post<PhotoCoverage>(`/flights/${id}/photos`, this.body());
    } catch (e) {
      this.fail('Photos', e);
      return;
    }
    this.draw(c);
    this.message.textContent =
      `${c.photos} photos saw ${(c.poc * 100).toFixed(1)} % of the field (twice: ${(c.pooc * 100).toFixed(1)} %; the plan ${(c.planned_poc * 100).toFixed(1)} %); ` +
      `${Math.round(c.gaps_m2).toLocaleString('en')} m² unseen` +
      (c.skipped.length ? `; skipped ${c.skipped.length}: ${c.skipped.slice(0, 3).join('; ')}` : '') +
      '.';
    this.message.dataset.poc = String(c.poc);
    this.refly.disabled = c.gaps_m2 <= 0;
  }

  private draw(c: PhotoCoverage): void {
    this.layer.clearLayers();
    L.geoJSON(c.geojson, {
      renderer: this.renderer,
      style: (f) =>
        f?.properties?.kind === 'gap'
          ? { color: '#c62828', weight: 2, fillColor: '#e53935', fillOpacity: 0.45 }
          : { color: '#37474f', weight: 1, opacity: 0.6, fillColor: '#90a4ae', fillOpacity: 0.12 },
      onEachFeature: (f, layer) => {
        const p = f.properties as Record<string, unknown>;
        layer.bindTooltip(
          p.kind === 'gap' ? `not seen: ${Math.round(Number(p.area_m2)).toLocaleString('en')} m²` : `${String(p.name)}, ${Number(p.height_m).toFixed(1)} m up`,
          { sticky: true },
        );
      },
    } as L.GeoJSONOptions).addTo(this.layer);
    this.layer.addTo(this.map);
  }

  private async reflyFromPhotos(): Promise<void> {
    const id = this.flightId();
    if (id === null || this.tags.length === 0) {
      this.fail('Refly', 'pick the flight’s photos first');
      return;
    }
    this.refly.disabled = true;
    try {
      const job = await api.post<{ id: number; params?: { refly?: { gaps_m2?: number } } }>(`/flights/${id}/refly`, this.body());
      this.message.className = 'fly-message';
      this.message.textContent = `Refly plan #${job.id} queued for ${Math.round(job.params?.refly?.gaps_m2 ?? 0).toLocaleString('en')} m² no photo saw. It opens from the Plan tab's plans of this mission.`;
      this.message.dataset.reflyJob = String(job.id);
    } catch (e) {
      this.fail('Refly', e);
    } finally {
      this.refly.disabled = false;
    }
  }
}
