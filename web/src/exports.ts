// Export buttons: every export route the server lists (GET /api/v1/formats, fetched once), per UAV,
// downloaded through <a download>; and "all as zip", bundled in the browser (zip.ts). Failures are shown in words.
import { API, ApiError, api } from './api.ts';
import { el, errorText } from './job-ui.ts';
import { uavColour } from './palette.ts';
import { zipStore, type ZipEntry } from './zip.ts';

/** A route of GET /plans/{id}/exports/{format} as GET /api/v1/formats lists them: the server's one
 *  table of export formats (src/export/formats.cpp), and kmz (made by kml). */
export interface ExportRoute {
  name: string;
  format: string;
  title: string;
}

let routes: Promise<ExportRoute[]> | null = null;

/** The server's export routes, fetched once (a failed fetch is tried again by the next panel). */
export function exportRoutes(): Promise<ExportRoute[]> {
  routes ??= api.get<{ routes: ExportRoute[] }>('/formats').then(
    (r) => r.routes,
    (e: unknown) => {
      routes = null;
      throw e;
    },
  );
  return routes;
}

/** The file name of a Content-Disposition header, or the fallback. */
export function dispositionName(header: string | null, fallback: string): string {
  const m = header?.match(/filename\*?=(?:UTF-8'')?"?([^";]+)"?/i);
  const name = m ? decodeURIComponent(m[1]) : fallback;
  return name.replace(/[/\\]/g, '_') || fallback;
}

export async function fetchFile(url: string, fallback: string): Promise<{ name: string; blob: Blob }> {
  let res: Response;
  try {
    res = await fetch(url);
  } catch {
    throw new ApiError(0, '', 'The server cannot be reached.');
  }
  if (!res.ok) {
    let err: { field?: string; message?: string } | undefined;
    try {
      err = ((await res.json()) as { error?: { field?: string; message?: string } }).error;
    } catch {
      /* not JSON */
    }
    throw new ApiError(res.status, err?.field ?? '', err?.message ?? `HTTP ${res.status}`);
  }
  return { name: dispositionName(res.headers.get('Content-Disposition'), fallback), blob: await res.blob() };
}

export function saveBlob(blob: Blob, name: string): void {
  const url = URL.createObjectURL(blob);
  const a = el('a', { href: url, download: name });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

/** The server's export options (GET /plans/{id}/exports/{format}?autopilot=&terrain_frame=&split_capacity=,
 *  docs/api.md): for which autopilot, heights in ArduPilot's terrain frame, missions split to the vehicle's
 *  item capacity (one zip per UAV). */
export interface ExportOptionValues {
  autopilot: string;
  terrainFrame: boolean;
  splitCapacity: boolean;
}

/** The query of an export URL: the UAV and the options that differ from the defaults. */
export function exportQuery(uav: string, o: ExportOptionValues): string {
  const q = new URLSearchParams({ uav });
  if (o.autopilot) q.set('autopilot', o.autopilot);
  if (o.terrainFrame) q.set('terrain_frame', 'true');
  if (o.splitCapacity) q.set('split_capacity', 'true');
  return q.toString();
}

function checkbox(testid: string, label: string, title: string): [HTMLLabelElement, HTMLInputElement] {
  const box = el('input', { type: 'checkbox', 'data-testid': testid });
  const l = el('label', { class: 'plan-export-option', title });
  l.append(box, document.createTextNode(` ${label}`));
  return [l, box];
}

export function exportsPanel(planId: number, uavIds: string[]): HTMLElement {
  const wrap = el('div', { class: 'plan-exports', 'data-testid': 'exports-panel' });
  const status = el('div', { class: 'plan-export-status', role: 'status', 'data-testid': 'export-status' });
  const zip = el('button', { type: 'button', 'data-testid': 'export-zip', disabled: '' }, 'All as zip');
  const options = el('div', { class: 'plan-export-row plan-export-options' });
  const autopilot = el('select', { 'data-testid': 'export-autopilot', title: 'The autopilot the files are for: its limits, commands and item capacity' });
  for (const [value, label] of [['', "Mission's autopilot"], ['px4', 'PX4'], ['ardupilot', 'ArduPilot'], ['dji', 'DJI'], ['litchi', 'Litchi']])
    autopilot.append(el('option', { value }, label));
  const [splitLabel, split] = checkbox('export-split', 'Split to item capacity', "Whole missions that fit the vehicle's mission storage, one zip per UAV");
  const [frameLabel, frame] = checkbox('export-terrain-frame', 'Terrain frame', "ArduPilot with a DEM: coverage heights relative to terrain (MAV_FRAME_GLOBAL_TERRAIN_ALT)");
  options.append(el('span', { class: 'plan-export-uav' }, 'Options'), autopilot, splitLabel, frameLabel);
  wrap.append(options, zip, status);
  status.textContent = 'Loading the export formats…';
  exportRoutes().then(
    (formats) => {
      status.textContent = '';
      fill(formats);
    },
    (e: ApiError) => {
      status.className = 'plan-export-status plan-error';
      status.textContent = `The export formats cannot be listed: ${errorText(e)}`;
    },
  );
  const url = (format: string, uav: string) =>
    `${API}/plans/${planId}/exports/${format}?` +
    exportQuery(uav, { autopilot: autopilot.value, terrainFrame: frame.checked, splitCapacity: split.checked });

  function fill(formats: ExportRoute[]): void {
    const rows = uavIds.map((uav, i) => {
      const row = el('div', { class: 'plan-export-row', 'data-uav': uav });
      const name = el('span', { class: 'plan-export-uav' });
      const sw = el('span', { class: 'plan-swatch' });
      sw.style.background = uavColour(i);
      name.append(sw, document.createTextNode(uav));
      row.append(name);
      for (const f of formats) {
        const b = el('button', { type: 'button', class: 'plan-small', 'data-testid': `export-${f.name}`, 'data-uav': uav, title: `${f.title} file of ${uav}` }, f.title);
        b.addEventListener('click', async () => {
          status.className = 'plan-export-status';
          status.textContent = `Downloading ${f.title} of ${uav}…`;
          try {
            const file = await fetchFile(url(f.name, uav), `${uav}.${f.name}`);
            saveBlob(file.blob, file.name);
            status.textContent = `Saved ${file.name}`;
          } catch (e) {
            status.className = 'plan-export-status plan-error';
            status.textContent = `${f.title} of ${uav}: ${errorText(e as ApiError)}`;
          }
        });
        row.append(b);
      }
      return row;
    });
    options.before(...rows);
    zip.disabled = false;
    zip.addEventListener('click', async () => {
      zip.disabled = true;
      status.className = 'plan-export-status';
      status.textContent = 'Collecting the files…';
      const entries: ZipEntry[] = [];
      const refused: string[] = [];
      const names = new Set<string>();
      for (const uav of uavIds)
        for (const f of formats) {
          try {
            const file = await fetchFile(url(f.name, uav), `${uav}.${f.name}`);
            let name = file.name;
            if (names.has(name)) name = `${uav}/${name}`;
            names.add(name);
            entries.push({ name, data: new Uint8Array(await file.blob.arrayBuffer()) });
          } catch (e) {
            refused.push(`${f.title} of ${uav}: ${errorText(e as ApiError)}`);
          }
        }
      zip.disabled = false;
      if (entries.length === 0) {
        status.className = 'plan-export-status plan-error';
        status.textContent = `No file could be exported. ${refused.join('; ')}`;
        return;
      }
      const bytes = zipStore(entries);
      saveBlob(new Blob([bytes as BlobPart], { type: 'application/zip' }), `plan-${planId}-exports.zip`);
      status.className = refused.length ? 'plan-export-status plan-error' : 'plan-export-status';
      status.textContent =
        `Saved plan-${planId}-exports.zip (${entries.length} files)` + (refused.length ? `; not included: ${refused.join('; ')}` : '');
    });
  }
  return wrap;
}
