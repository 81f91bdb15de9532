// Maps without internet (issue 29, docs/offline-maps.md): `uavcover serve --tiles FILE.mbtiles` with a
// file scripts/make-tiles makes from the example DEM (its hillshade) at test time. The app asks
// /tiles/metadata.json at start, makes the server's tiles its base layer, requests them from /tiles/
// inside their bounds and zoom levels only, and draws them; with online tiles too, a layer control offers
// both, the server's selected. Screenshot tiles-offline-1440x900.png in $UAVCOVER_WEB_ARTIFACTS.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import * as h from './harness.mjs';

let server, browser, tmp, meta, file;
const problems = [];
const TILE = /\/tiles\/(\d+)\/(\d+)\/(\d+)$/;

before(async () => {
  tmp = mkdtempSync(join(tmpdir(), 'uavcover-tiles-e2e-'));
  file = join(tmp, 'hill.mbtiles');
  execFileSync('python3', [join(h.repo, 'scripts/make-tiles'), join(h.repo, 'examples/hill-dem.tif'), file, '--hillshade', '--z-factor', '3', '--max-zoom', '17'], { stdio: 'pipe' });
  server = await h.startServer({ extraArgs: ['--tiles', file] });
  browser = await h.launchBrowser();
  meta = await (await fetch(`${server.base}/tiles/metadata.json`)).json();
});

after(async () => {
  await browser?.close();
  await server?.stop();
  if (tmp) rmSync(tmp, { recursive: true, force: true });
  assert.deepEqual(problems.flat(), []);
});

/** Opens the app at `query`, recording every tile request to /tiles/ and its answer. */
async function open(query, size = { width: 1440, height: 900 }) {
  const p = await h.openPage(browser, size);
  problems.push(p.problems);
  const asked = [];
  p.page.on('response', (r) => {
    const m = new URL(r.url()).pathname.match(TILE);
    if (m) asked.push({ z: +m[1], x: +m[2], y: +m[3], status: r.status(), type: r.headers()['content-type'] });
  });
  await p.page.goto(`${server.base}/${query}`);
  await p.page.waitForSelector('#tabs button[data-tab=plan]');
  return { ...p, asked };
}

/** The loaded tiles of the server's layer in the main map, with what their pixels hold. */
function drawnTiles(page) {
  return page.evaluate(() =>
    // (a tile the file lacks, such as a fully transparent one GDAL left out, is a 404: not drawn)
    [...document.querySelectorAll('#map .offline-tiles img.leaflet-tile-loaded')].filter((img) => img.naturalWidth > 0).map((img) => {
      const c = document.createElement('canvas');
      c.width = img.naturalWidth;
      c.height = img.naturalHeight;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      let opaque = 0, grey = 0, min = 255, max = 0;
      for (let i = 0; i < d.length; i += 4) {
        if (d[i + 3] !== 255) continue;
        opaque++;
        if (d[i] === d[i + 1] && d[i + 1] === d[i + 2]) grey++;
        min = Math.min(min, d[i]);
        max = Math.max(max, d[i]);
      }
      return { src: img.src, width: img.naturalWidth, opaque, grey, min, max };
    }),
  );
}

async function settled(page) {
  await page.waitForFunction(() => {
    const layer = document.querySelector('#map .offline-tiles');
    return !!layer && layer.querySelectorAll('img.leaflet-tile-loaded').length > 0 && layer.querySelectorAll('img.leaflet-tile:not(.leaflet-tile-loaded)').length === 0;
  }, null, { timeout: 30000 });
  await page.waitForTimeout(400); // the fade-in
}

test('the server says where its tiles are', () => {
  assert.equal(meta.available, true);
  assert.equal(meta.url, '/tiles/{z}/{x}/{y}');
  assert.equal(meta.format, 'png');
  assert.equal(meta.maxzoom, 17);
  assert.ok(meta.minzoom < meta.maxzoom);
  const [w, s, e, n] = meta.bounds;
  assert.ok(w < 22.906 && 22.906 < e && s < 40.6035 && 40.6035 < n, `bounds ${meta.bounds}`);
});

test('without internet tiles the map draws the server\'s tiles from /tiles/', async () => {
  const { page, asked } = await open('?tiles=off');
  await settled(page);
  const drawn = await drawnTiles(page);
  assert.ok(drawn.length > 0, 'no tile drawn');
  for (const t of drawn) {
    assert.match(new URL(t.src).pathname, TILE);
    assert.equal(new URL(t.src).origin, server.base);
    assert.equal(t.width, 256);
  }
  // the hillshade: grey pixels, shaded (not one flat value), on most of the tiles that are drawn
  const shaded = drawn.filter((t) => t.opaque > 1000 && t.grey === t.opaque && t.max - t.min > 20);
  assert.ok(shaded.length > 0, JSON.stringify(drawn.map(({ opaque, grey, min, max }) => ({ opaque, grey, min, max }))));
  assert.ok(asked.length > 0);
  assert.ok(asked.some((a) => a.status === 200 && a.type === 'image/png'), JSON.stringify(asked));
  // only inside the tiles' zoom levels and bounds
  for (const a of asked) assert.ok(a.z >= meta.minzoom && a.z <= meta.maxzoom, JSON.stringify(a));
  assert.equal(await page.locator('#map .leaflet-control-layers').count(), 0); // nothing to choose from
  await h.shot(page, 'tiles-offline-1440x900');

  // zoomed in past the finest level the finest tiles are enlarged: nothing finer is asked for
  for (let i = 0; i < 4; i++) {
    await page.click('#map .leaflet-control-zoom-in');
    await page.waitForTimeout(350);
  }
  await settled(page);
  assert.ok((await drawnTiles(page)).length > 0);
  for (const a of asked) assert.ok(a.z <= meta.maxzoom, JSON.stringify(a));
  await page.context().close();
});

test('with online tiles too, a layer control offers both, the server\'s selected', async () => {
  // an "online" template nobody answers (the server's 404s): the test needs no internet
  const online = encodeURIComponent(`${server.base}/no-such-online-tiles/{z}/{x}/{y}.png`);
  const { page, asked } = await open(`?tiles=${online}`);
  await settled(page);
  const control = page.locator('#map .leaflet-control-layers');
  await control.waitFor();
  await control.hover();
  const labels = control.locator('.leaflet-control-layers-base label');
  assert.deepEqual((await labels.allTextContents()).map((s) => s.trim()), ['Offline tiles (server)', 'OpenStreetMap']);
  assert.equal(await labels.nth(0).locator('input').isChecked(), true);
  const before = asked.length;
  assert.ok(before > 0);
  await labels.nth(1).click();
  await page.waitForFunction(() => !document.querySelector('#map .offline-tiles'));
  await labels.nth(0).click();
  await settled(page);
  assert.ok((await drawnTiles(page)).length > 0);
  await page.context().close();
});

test('the comparison\'s side-by-side maps draw the server\'s tiles too', async () => {
  const olive = JSON.parse(readFileSync(join(h.repo, 'examples/olive-grove.json'), 'utf8'));
  const m = await server.api('/missions', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ ...olive, name: 'tiles compare' }) });
  const { page } = await open(`?tiles=off&mission=${m.id}#plan`);
  await page.click('[data-testid=compare-section] > summary');
  await page.waitForSelector('[data-testid=compare-planner][data-planner=darp]');
  for (const cb of await page.locator('[data-testid=compare-planner]').all()) await cb.setChecked(['darp', 'boustrophedon'].includes(await cb.getAttribute('data-planner')));
  await page.click('[data-testid=compare-start]');
  await page.waitForSelector('[data-testid=compare-side-by-side]:not([disabled])', { timeout: 180000 });
  await page.click('[data-testid=compare-side-by-side]');
  await page.waitForFunction(
    () => {
      const maps = [...document.querySelectorAll('[data-testid=compare-maps] .plan-overlay-map')];
      return maps.length === 2 && maps.every((el) => [...el.querySelectorAll('.offline-tiles img.leaflet-tile-loaded')].some((i) => i.naturalWidth > 0 && new URL(i.src).pathname.startsWith('/tiles/')));
    },
    null,
    { timeout: 30000 },
  );
  await page.waitForTimeout(400);
  await h.shot(page, 'tiles-offline-side-by-side');
  await page.context().close();
});

test('over HTTP: HEAD, bad coordinates, and the token like every other route', async () => {
  const tokenFile = join(tmp, 'token');
  const token = 'offline-tiles-token-0123456789';
  writeFileSync(tokenFile, `${token}\n`);
  const guarded = await h.startServer({ extraArgs: ['--tiles', file, '--token-file', tokenFile] });
  try {
    const z = meta.maxzoom, n = 2 ** z, lat = (40.6035 * Math.PI) / 180;
    const x = Math.floor(((22.906 + 180) / 360) * n), y = Math.floor(((1 - Math.asinh(Math.tan(lat)) / Math.PI) / 2) * n);
    const auth = { Authorization: `Bearer ${token}` };
    const denied = await fetch(`${guarded.base}/tiles/${z}/${x}/${y}`);
    assert.equal(denied.status, 401);
    assert.equal((await denied.json()).error.field, 'authorization');
    assert.equal((await fetch(`${guarded.base}/tiles/metadata.json`)).status, 401);
    const got = await fetch(`${guarded.base}/tiles/${z}/${x}/${y}.png`, { headers: auth });
    assert.equal(got.status, 200);
    assert.equal(got.headers.get('content-type'), 'image/png');
    assert.equal(got.headers.get('cache-control'), 'max-age=86400');
    const bytes = Buffer.from(await got.arrayBuffer());
    assert.deepEqual([...bytes.subarray(0, 4)], [0x89, 0x50, 0x4e, 0x47]);
    const head = await fetch(`${guarded.base}/tiles/${z}/${x}/${y}`, { method: 'HEAD', headers: auth });
    assert.equal(head.status, 200);
    assert.equal(Number(head.headers.get('content-length')), bytes.length);
    assert.equal((await head.arrayBuffer()).byteLength, 0);
    for (const [path, field] of [[`/tiles/31/0/0`, 'z'], [`/tiles/${z}/${n}/0`, 'x'], [`/tiles/${z}/0/y`, 'y']]) {
      const bad = await fetch(`${guarded.base}${path}`, { headers: auth });
      assert.equal(bad.status, 400, path);
      assert.equal((await bad.json()).error.field, field, path);
    }
    const absent = await fetch(`${guarded.base}/tiles/${z}/${x}/${n - 1 - y}`, { headers: auth });
    assert.equal(absent.status, 404);
    assert.ok((await absent.json()).error.message);
  } finally {
    await guarded.stop();
  }
});
