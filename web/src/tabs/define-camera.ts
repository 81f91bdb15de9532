// The Define tab's camera section (issue 11): the mission's camera from the catalog, the paper's field
// of view + overlap or the file's sensor, or no camera and a spacing; altitude, side overlap, HFOV and
// gimbal pitch; the spacing, GSD and footprint the server computes when it checks the document
// (POST /missions/validate), whose errors are shown beside the fields. And a UAV's own camera block,
// which follows the mission's.
import { el } from '../dom.ts';
import { api, ApiError } from '../api.ts';
import { areaPolygons, corridorOf, structureOf, type MissionDoc } from '../mission-doc.ts';
import { errorText } from './missions.ts';
import { field, num, round, section, type DefineErrors } from './define-errors.ts';

export interface CatalogCamera {
  id: number;
  name: string;
  sensor_width_mm: number;
  focal_length_mm: number;
  image_width_px: number;
  hfov_deg: number;
}
interface Validated {
  spacing_m: number;
  gsd_m: number | null;
  footprint_m: number | null;
  altitude_m: number;
  altitude_source: string;
}
type Uav = Record<string, unknown>;

export interface CameraHost {
  doc(): MissionDoc;
  commit(d: MissionDoc): void;
  /** the camera catalog */
  cameras(): CatalogCamera[];
  /** the UAV rows drawn again (their cameras follow the mission's) */
  renderUavs(): void;
  errors: Pick<DefineErrors, 'show' | 'clear' | 'showGeneral' | 'clearGeneral'>;
}

export class CameraSection {
  private cameraSelect: HTMLSelectElement;
  private altitudeInput: HTMLInputElement;
  private overlapInput: HTMLInputElement;
  private hfovInput: HTMLInputElement;
  private spacingInput: HTMLInputElement;
  private gimbalInput: HTMLInputElement;
  private spacingValue: HTMLElement;
  private gsdValue: HTMLElement;
  private footprintValue: HTMLElement;
  private validateTimer = 0;
  private validateSeq = 0;

  constructor(
    panel: HTMLElement,
    private host: CameraHost,
  ) {
    const cam = section(panel, 'Camera and spacing');
    this.cameraSelect = el('select', { 'data-testid': 'camera-select' });
    this.cameraSelect.addEventListener('change', () => this.changed(true));
    field(cam, 'Camera', 'camera', this.cameraSelect);
    this.altitudeInput = el('input', { type: 'number', min: '1', step: '1', 'data-testid': 'altitude-input' });
    field(cam, 'Altitude', 'altitude_m camera.altitude_m', this.altitudeInput, 'm');
    this.overlapInput = el('input', { type: 'number', min: '0', max: '99', step: '1', 'data-testid': 'overlap-input' });
    field(cam, 'Side overlap', 'camera.overlap camera.side_overlap', this.overlapInput, '%');
    this.hfovInput = el('input', { type: 'number', min: '1', max: '179', step: 'any', 'data-testid': 'hfov-input' });
    field(cam, 'HFOV', 'camera.hfov_deg', this.hfovInput, '°');
    this.spacingInput = el('input', { type: 'number', min: '0.1', step: 'any', 'data-testid': 'spacing-input' });
    field(cam, 'Spacing', 'spacing_m', this.spacingInput, 'm');
    this.gimbalInput = el('input', { type: 'number', min: '-90', max: '0', step: '1', placeholder: '-90', 'data-testid': 'gimbal-input', title: 'camera pitch: -90° looks straight down (the default), 0° at the horizon' });
    field(cam, 'Gimbal pitch', 'camera.gimbal_pitch_deg', this.gimbalInput, '°');
    for (const i of [this.altitudeInput, this.overlapInput, this.hfovInput, this.spacingInput, this.gimbalInput]) i.addEventListener('change', () => this.changed(false));
    const out = el('dl', { class: 'define-values' });
    const value = (label: string, testid: string, title: string) => {
      out.append(el('dt', { title }, label));
      const dd = el('dd', { 'data-testid': testid }, '—');
      out.appendChild(dd);
      return dd;
    };
    this.spacingValue = value('Spacing ds', 'spacing-value', 'distance between neighbouring sweep lines');
    this.gsdValue = value('GSD', 'gsd-value', 'ground sampling distance (sensor cameras)');
    this.footprintValue = value('Footprint', 'footprint-value', 'width of the image on the ground');
    cam.appendChild(out);
  }

  /** the side overlap as entered (in %) */
  overlap(): string {
    return this.overlapInput.value;
  }

  private cameraMode(): string {
    const c = this.host.doc().camera as Record<string, unknown> | undefined;
    if (!c || typeof c !== 'object') return 'none';
    if (typeof c.catalog_id === 'number') return `cat:${c.catalog_id}`;
    if (typeof c.hfov_deg === 'number' && c.sensor_width_mm === undefined) return 'paper';
    const match = this.host.cameras().find(
      (k) => k.sensor_width_mm === c.sensor_width_mm && k.focal_length_mm === c.focal_length_mm && k.image_width_px === c.image_width_px,
    );
    return match ? `cat:${match.id}` : 'custom';
  }

  /** the document's camera block (or spacing) into the inputs */
  render(): void {
    const doc = this.host.doc();
    const cameras = this.host.cameras();
    const mode = this.cameraMode();
    const sel = this.cameraSelect;
    sel.replaceChildren(
      el('option', { value: 'none' }, 'No camera: give the spacing'),
      el('option', { value: 'paper' }, 'Field of view + overlap (paper)'),
    );
    if (mode === 'custom') sel.appendChild(el('option', { value: 'custom' }, 'Sensor from the mission file'));
    if (cameras.length) {
      const g = el('optgroup', { label: 'Camera catalog' });
      for (const c of cameras) g.appendChild(el('option', { value: `cat:${c.id}` }, c.name));
      sel.appendChild(g);
    }
    if (mode.startsWith('cat:') && !sel.querySelector(`option[value="${mode}"]`))
      sel.appendChild(el('option', { value: mode }, `catalog camera #${mode.slice(4)}`));
    sel.value = mode;
    const c = (doc.camera as Record<string, unknown> | undefined) ?? {};
    const pct = (x: unknown) => (typeof x === 'number' ? String(round(x * 100, 2)) : '');
    const alt = mode === 'none' ? doc.altitude_m : c.altitude_m;
    this.altitudeInput.value = typeof alt === 'number' ? String(alt) : '';
    this.altitudeInput.placeholder = mode === 'none' ? '40' : '';
    this.overlapInput.value = mode === 'paper' ? pct(c.overlap) : pct(c.side_overlap);
    // the paper's po counts both sides of an image: up to 199 % (its search-and-rescue mission flew 160 %)
    this.overlapInput.max = mode === 'paper' ? '199' : '99';
    this.hfovInput.value = typeof c.hfov_deg === 'number' ? String(c.hfov_deg) : '';
    this.spacingInput.value = typeof doc.spacing_m === 'number' ? String(doc.spacing_m) : '';
    const show = (input: HTMLElement, on: boolean) => ((input.parentElement as HTMLElement).hidden = !on);
    show(this.overlapInput, mode !== 'none');
    show(this.hfovInput, mode === 'paper');
    show(this.spacingInput, mode === 'none');
    this.gimbalInput.value = typeof c.gimbal_pitch_deg === 'number' ? String(c.gimbal_pitch_deg) : '';
    show(this.gimbalInput, mode !== 'none');
  }

  /** the inputs into the document's camera block (or spacing) */
  private changed(modeChanged: boolean): void {
    const mode = this.cameraSelect.value;
    const doc = this.host.doc();
    const old = (doc.camera as Record<string, unknown> | undefined) ?? {};
    const d: MissionDoc = { ...doc };
    const alt = num(this.altitudeInput.value) ?? (typeof d.altitude_m === 'number' ? d.altitude_m : undefined) ?? 40;
    let ov = num(this.overlapInput.value);
    const frac = ov === undefined ? undefined : ov / 100;
    const put = (o: Record<string, unknown>) => {
      for (const k of Object.keys(o)) if (o[k] === undefined) delete o[k];
      return o;
    };
    if (mode === 'none') {
      delete d.camera;
      d.altitude_m = num(this.altitudeInput.value) ?? 40;
      const s = num(this.spacingInput.value);
      d.spacing_m = modeChanged ? (s ?? 20) : s;
      if (d.spacing_m === undefined) delete d.spacing_m;
    } else {
      delete d.spacing_m;
      delete d.altitude_m;
      if (mode === 'paper') {
        d.camera = put({
          altitude_m: alt,
          hfov_deg: num(this.hfovInput.value) ?? (modeChanged ? 73.4 : undefined),
          overlap: modeChanged && frac === undefined ? 0.5 : frac,
        });
      } else if (mode === 'custom') {
        const c: Record<string, unknown> = { ...old, altitude_m: alt, side_overlap: frac ?? (modeChanged ? 0.7 : undefined) };
        delete c.overlap;
        delete c.hfov_deg;
        d.camera = put(c);
      } else {
        d.camera = put({ catalog_id: Number(mode.slice(4)), altitude_m: alt, side_overlap: frac ?? (modeChanged ? 0.7 : undefined) });
      }
    }
    if (d.camera && typeof d.camera === 'object') {
      const cam = d.camera as Record<string, unknown>;
      const g = num(this.gimbalInput.value);
      if (g === undefined) delete cam.gimbal_pitch_deg;
      else cam.gimbal_pitch_deg = g;
    }
    d.uavs = uavCameras(this.host.cameras(), d, Array.isArray(doc.uavs) ? (doc.uavs as Uav[]) : []);
    this.host.commit(d);
    if (modeChanged) this.render();
    if (modeChanged) this.host.renderUavs();
  }

  /** the document checked by the server soon (the last change wins) */
  scheduleValidate(delay = 300): void {
    clearTimeout(this.validateTimer);
    this.validateTimer = window.setTimeout(() => void this.validate(), delay);
  }

  private async validate(): Promise<void> {
    const seq = ++this.validateSeq;
    const doc = this.host.doc();
    if (areaPolygons(doc).length === 0 && !corridorOf(doc) && !structureOf(doc)) {
      this.host.errors.clear();
      for (const v of [this.spacingValue, this.gsdValue, this.footprintValue]) v.textContent = '—';
      this.spacingValue.title = 'draw the area first';
      return;
    }
    try {
      const r = await api.post<Validated>('/missions/validate', doc);
      if (seq !== this.validateSeq) return;
      this.host.errors.clear();
      this.host.errors.clearGeneral();
      this.spacingValue.textContent = `${r.spacing_m.toFixed(r.spacing_m < 10 ? 2 : 1)} m`;
      this.spacingValue.title = `at ${r.altitude_m} m altitude (${r.altitude_source})`;
      this.gsdValue.textContent = r.gsd_m === null ? '— (sensor cameras only)' : `${(r.gsd_m * 100).toFixed(2)} cm/px`;
      this.footprintValue.textContent = r.footprint_m === null ? '—' : `${r.footprint_m.toFixed(1)} m`;
    } catch (e) {
      if (seq !== this.validateSeq) return;
      this.host.errors.clear();
      for (const v of [this.spacingValue, this.gsdValue, this.footprintValue]) v.textContent = '—';
      if (e instanceof ApiError && e.status === 422) {
        this.host.errors.clearGeneral();
        this.host.errors.show(e.field, e.message);
      } else this.host.errors.showGeneral(errorText(e));
    }
  }
}

/** A UAV's own camera (a catalog camera other than the mission's) as the library wants it: the
 * mission camera's altitude and overlaps with that camera's sensor (or HFOV in the paper's convention). */
export function ownCamera(cameras: CatalogCamera[], d: MissionDoc, camId: number): Record<string, unknown> | null {
  const mc = d.camera as Record<string, unknown> | undefined;
  const k = cameras.find((c) => c.id === camId);
  if (!mc || typeof mc !== 'object' || !k) return null;
  const out: Record<string, unknown> = { altitude_m: mc.altitude_m };
  const paper = typeof mc.overlap === 'number' || (typeof mc.hfov_deg === 'number' && mc.sensor_width_mm === undefined && mc.catalog_id === undefined);
  if (paper) Object.assign(out, { overlap: mc.overlap, hfov_deg: k.hfov_deg });
  else Object.assign(out, { side_overlap: mc.side_overlap, sensor_width_mm: k.sensor_width_mm, focal_length_mm: k.focal_length_mm, image_width_px: k.image_width_px });
  for (const key of ['front_overlap', 'gimbal_pitch_deg']) if (mc[key] !== undefined) out[key] = mc[key];
  for (const key of Object.keys(out)) if (out[key] === undefined) delete out[key];
  return out;
}

/** The catalog camera a UAV's own camera block is, if any. */
export function uavCameraId(cameras: CatalogCamera[], u: Uav): number | null {
  const c = u.camera as Record<string, unknown> | undefined;
  if (!c || typeof c !== 'object') return null;
  const k = cameras.find((x) =>
    typeof c.sensor_width_mm === 'number' ? x.sensor_width_mm === c.sensor_width_mm && x.focal_length_mm === c.focal_length_mm && x.image_width_px === c.image_width_px : x.hfov_deg === c.hfov_deg,
  );
  return k ? k.id : null;
}

/** UAVs whose own camera follows the mission's camera (altitude, overlaps); none without one. */
export function uavCameras(cameras: CatalogCamera[], d: MissionDoc, list: Uav[]): Uav[] {
  return list.map((u) => {
    if (!u.camera) return u;
    const id = uavCameraId(cameras, u);
    const n = { ...u };
    const own = id === null ? null : ownCamera(cameras, d, id);
    if (own) n.camera = own;
    else if (!d.camera) delete n.camera;
    return n;
  });
}
