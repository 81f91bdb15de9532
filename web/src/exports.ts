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
  const zip = el('button', { type: 'button', 'data-testid': 'export-zip', disabled: '' }, 'All as zip');
  wrap.append(zip, status);
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
    `${API}/plans/${planId}/exports/${format}?uav=${encodeURIComponent(uav)}`;

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
    zip.before(...rows);
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
