// Shared pieces of the browser tests (and bench/web): the real `uavcover serve` on a free port with a
// temporary SQLite database seeded from examples/, headless Debian Chromium through playwright-core,
// a page that records console errors and warnings, and small helpers (API calls, screenshots, tabs,
// map points).
//   UAVCOVER_CLI            the uavcover binary (default <repo>/build/uavcover)
//   UAVCOVER_WEB_ARTIFACTS  the screenshot folder (default <repo>/build/web-screenshots)
//   CHROMIUM                the browser (default /usr/bin/chromium)
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const repo = resolve(dirname(fileURLToPath(import.meta.url)), '../../..');
export const cli = process.env.UAVCOVER_CLI || join(repo, 'build/uavcover');
export const shots = process.env.UAVCOVER_WEB_ARTIFACTS || join(repo, 'build/web-screenshots');
export const dist = join(repo, 'web/dist');

export function freePort() {
  return new Promise((ok, fail) => {
    const s = createServer();
    s.on('error', fail);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => ok(port));
    });
  });
}

/**
 * Starts `uavcover serve` over a fresh SQLite database in a temporary folder (or the database file
 * `db`, kept), seeded with examples/, serving web/dist. Resolves once /healthz answers: { base, api(path, init), log(), stop() }.
 */
export async function startServer({ workers = 2, extraArgs = [], db = null } = {}) {
  assert.ok(existsSync(cli), `no uavcover binary at ${cli} (set UAVCOVER_CLI)`);
  assert.ok(existsSync(join(dist, 'index.html')), `no built app in ${dist} (run scripts/build-web)`);
  const tmp = mkdtempSync(join(tmpdir(), 'uavcover-web-e2e-'));
  const port = await freePort();
  const proc = spawn(
    cli,
    ['serve', '--listen', `127.0.0.1:${port}`, '--db', `sqlite:${db ?? join(tmp, 't.db')}`, '--seed-dir', join(repo, 'examples'), '--static', dist, '--workers', String(workers), ...extraArgs],
    { stdio: ['ignore', 'pipe', 'pipe'] },
  );
  let log = '';
  proc.stdout.on('data', (d) => (log += d));
  proc.stderr.on('data', (d) => (log += d));
  let base = `http://127.0.0.1:${port}`;
  const deadline = Date.now() + 20000;
  for (;;) {
    const m = log.match(/serving on (http:\/\/[\d.:]+)/);
    if (m) base = m[1];
    try {
      if ((await fetch(`${base}/healthz`)).ok) break;
    } catch {
      /* not yet */
    }
    assert.ok(proc.exitCode === null, `the server stopped: ${log}`);
    assert.ok(Date.now() < deadline, `the server did not answer: ${log}`);
    await new Promise((r) => setTimeout(r, 100));
  }
  const api = async (path, init) => {
    const res = await fetch(`${base}/api/v1${path}`, init);
    const body = await res.text();
    assert.ok(res.ok, `${path}: HTTP ${res.status} ${body}`);
    return body ? JSON.parse(body) : undefined;
  };
  return {
    base,
    api,
    log: () => log,
    async stop() {
      if (proc.exitCode === null) {
        proc.kill('SIGTERM');
        await new Promise((r) => proc.once('exit', r));
      }
      rmSync(tmp, { recursive: true, force: true });
    },
  };
}

export function launchBrowser() {
  mkdirSync(shots, { recursive: true });
  return chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--no-sandbox', '--headless', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--no-first-run', '--disable-sync'],
  });
}

/** A page of its own context; `problems` collects console errors and warnings and page errors. */
export async function openPage(browser, { width = 1280, height = 800 } = {}) {
  const context = await browser.newContext({ viewport: { width, height }, acceptDownloads: true });
  const page = await context.newPage();
  const problems = [];
  page.on('console', (m) => {
    // Chromium itself logs every 4xx answer; the app shows those in words
    if (/^Failed to load resource: the server responded with a status of 4\d\d/.test(m.text())) return;
    if (m.type() === 'error' || m.type() === 'warning') problems.push(`${m.type()}: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  return { page, context, problems };
}

export async function shot(page, name) {
  await page.screenshot({ path: join(shots, `${name}.png`) });
}

export async function tab(page, name) {
  await page.click(`#tabs button[data-tab=${name}]`);
}

/** The page pixel at fractions (fx, fy) of the map's box. */
export async function mapPoint(page, fx, fy) {
  const box = await page.locator('#map').boundingBox();
  return [box.x + fx * box.width, box.y + fy * box.height];
}

/**
 * Waits until the plan's tiles in view are drawn (plan-layers.ts: data-state="ready" on the tile
 * layer, no tile loading, and still so after the map's zoom animation, two frames later).
 */
export async function planDrawn(page, selector = '#map', timeout = 120000) {
  const settled = (sel) => {
    const c = document.querySelector(`${sel} .plan-tiles`);
    return !!c && c.dataset.state === 'ready' && !document.querySelector(`${sel} .leaflet-zoom-anim`) && c.querySelectorAll('.leaflet-tile:not(.leaflet-tile-loaded)').length === 0;
  };
  for (;;) {
    await page.waitForFunction(settled, selector, { timeout });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    if (await page.evaluate(settled, selector)) return;
  }
}

/** EXIF's degrees-minutes-seconds as GDAL's JPEG driver takes them: "(d) (m) (s)". */
function dms(deg) {
  const a = Math.abs(deg);
  const d = Math.floor(a);
  const m = Math.floor((a - d) * 60);
  const s = ((a - d) * 60 - m) * 60;
  return `(${d}) (${m}) (${s.toFixed(4)})`;
}

/**
 * Geotagged JPEGs made with GDAL's own tools (docs/photos.md): one 32 x 24 grey image (gdal_create), then a
 * copy per photo with its EXIF GPS position, GPS altitude, heading and 35 mm focal length (gdal_translate
 * -mo EXIF_...). photos: [{name, lat, lon, alt_m, yaw_deg}]; returns the files' paths.
 */
export async function makePhotos(photos, { focal35 = 24 } = {}) {
  const { execFileSync } = await import('node:child_process');
  const dir = mkdtempSync(join(tmpdir(), 'uavcover-photos-'));
  const base = join(dir, 'base.tif');
  execFileSync('gdal_create', ['-q', '-of', 'GTiff', '-outsize', '32', '24', '-bands', '3', '-burn', '128', base]);
  return photos.map((p) => {
    const file = join(dir, p.name);
    execFileSync('gdal_translate', [
      '-q', '-of', 'JPEG',
      '-mo', `EXIF_GPSLatitude=${dms(p.lat)}`, '-mo', `EXIF_GPSLatitudeRef=${p.lat < 0 ? 'S' : 'N'}`,
      '-mo', `EXIF_GPSLongitude=${dms(p.lon)}`, '-mo', `EXIF_GPSLongitudeRef=${p.lon < 0 ? 'W' : 'E'}`,
      '-mo', `EXIF_GPSAltitude=(${p.alt_m})`, '-mo', `EXIF_GPSImgDirection=(${p.yaw_deg ?? 0})`,
      '-mo', `EXIF_FocalLengthIn35mmFilm=${focal35}`,
      base, file,
    ]);
    return file;
  });
}
