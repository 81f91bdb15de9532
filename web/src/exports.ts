// Export buttons: every format the server exports, per UAV, downloaded through <a download>; and
// "all as zip", bundled in the browser (zip.ts). Failures are shown in words.
import { API, ApiError } from './api.ts';
import { el, errorText } from './job-ui.ts';
import { uavColour } from './palette.ts';
import { zipStore, type ZipEntry } from './zip.ts';

export const FORMATS: { name: string; label: string }[] = [
  { name: 'qgc', label: 'QGC' },
  { name: 'wpl', label: 'WPL' },
  { name: 'kml', label: 'KML' },
  { name: 'kmz', label: 'KMZ' },
  { name: 'dji', label: 'DJI' },
  { name: 'litchi', label: 'Litchi' },
  { name: 'csv', label: 'CSV' },
  { name: 'geojson', label: 'GeoJSON' },
  { name: 'trajectory', label: 'Trajectory' },
];

/** The file name of a Content-Disposition header, or the fallback. */
export function dispositionName(header: string | null, fallback: string): string {
  const m = header?.match(/filename\*?=(?:UTF-8'')?"?([^";]+)"?/i);
  const name = m ? decodeURIComponent(m[1]) : fallback;
  return name.replace(/[/\\]/g, '_') || fallback;
}

async function fetchFile(url: string, fallback: string): Promise<{ name: string; blob: Blob }> {
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

export function exportsPanel(planId: number, uavIds: string[]): HTMLElement {
  const wrap = el('div', { class: 'plan-exports', 'data-testid': 'exports-panel' });
  const status = el('div', { class: 'plan-export-status', role: 'status', 'data-testid': 'export-status' });
  const url = (format: string, uav: string) =>
    `${API}/plans/${planId}/exports/${format}?uav=${encodeURIComponent(uav)}`;
  uavIds.forEach((uav, i) => {
    const row = el('div', { class: 'plan-export-row', 'data-uav': uav });
    const name = el('span', { class: 'plan-export-uav' });
    const sw = el('span', { class: 'plan-swatch' });
    sw.style.background = uavColour(i);
    name.append(sw, document.createTextNode(uav));
    row.append(name);
    for (const f of FORMATS) {
      const b = el('button', { type: 'button', class: 'plan-small', 'data-testid': `export-${f.name}`, 'data-uav': uav, title: `${f.label} file of ${uav}` }, f.label);
      b.addEventListener('click', async () => {
        status.className = 'plan-export-status';
        status.textContent = `Downloading ${f.label} of ${uav}…`;
        try {
          const file = await fetchFile(url(f.name, uav), `${uav}.${f.name}`);
          saveBlob(file.blob, file.name);
          status.textContent = `Saved ${file.name}`;
        } catch (e) {
          status.className = 'plan-export-status plan-error';
          status.textContent = `${f.label} of ${uav}: ${errorText(e as ApiError)}`;
        }
      });
      row.append(b);
    }
    wrap.append(row);
  });
  const zip = el('button', { type: 'button', 'data-testid': 'export-zip' }, 'All as zip');
  zip.addEventListener('click', async () => {
    zip.disabled = true;
    status.className = 'plan-export-status';
    status.textContent = 'Collecting the files…';
    const entries: ZipEntry[] = [];
    const refused: string[] = [];
    const names = new Set<string>();
    for (const uav of uavIds)
      for (const f of FORMATS) {
        try {
          const file = await fetchFile(url(f.name, uav), `${uav}.${f.name}`);
          let name = file.name;
          if (names.has(name)) name = `${uav}/${name}`;
          names.add(name);
          entries.push({ name, data: new Uint8Array(await file.blob.arrayBuffer()) });
        } catch (e) {
          refused.push(`${f.label} of ${uav}: ${errorText(e as ApiError)}`);
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
  wrap.append(zip, status);
  return wrap;
}
