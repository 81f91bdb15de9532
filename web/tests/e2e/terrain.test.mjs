// End-to-end, issue 31: terrain in the web app against the real `uavcover serve`. The operator draws a
// field, uploads a GeoTIFF elevation model (written by GDAL's own gdal_translate in the test) in the
// Define tab, turns terrain following on with a tolerance and a climb limit, plans, and sees the ground
// profile under each UAV's path with its band of heights above ground; screenshots at 1440x900 and
// 768x1024.
//   UAVCOVER_CLI   the uavcover binary (default <repo>/build/uavcover)
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import * as h from './harness.mjs';

let server, browser, page, api, tmp;
const stamp = Date.now();

before(async () => {
  tmp = mkdtempSync(join(tmpdir(), 'uavcover-terrain-e2e-'));
  server = await h.startServer();
  api = server.api;
  browser = await h.launchBrowser();
  ({ page } = await h.openPage(browser, { width: 1440, height: 900 }));
  await page.goto(`${server.base}/?tiles=off`);
  await page.waitForSelector('#tabs button[data-tab=plan]');
  await h.tab(page, 'define');
});

after(async () => {
  await browser?.close();
  await server?.stop();
  if (tmp) rmSync(tmp, { recursive: true, force: true });
});

/** A GeoTIFF (EPSG:4326) over `bbox` with a 60 m hill in its middle on a 200 m plain: an ESRI ASCII grid
 * turned into a GeoTIFF by gdal_translate. */
function hillTiff([w, s, e, n]) {
  const mx = (e - w) * 0.5, my = (n - s) * 0.5;
  const x0 = w - mx, y0 = s - my, x1 = e + mx, y1 = n + my;
  const cols = 120, cell = (x1 - x0) / cols, rows = Math.ceil((y1 - y0) / cell);
  const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, sigma = (e - w) / 4;
  let asc = `ncols ${cols}\nnrows ${rows}\nxllcorner ${x0}\nyllcorner ${y0}\ncellsize ${cell}\nNODATA_value -9999\n`;
  for (let r = 0; r < rows; r++) {
    const y = y0 + (rows - r - 0.5) * cell;
    const row = [];
    for (let c = 0; c < cols; c++) {
      const x = x0 + (c + 0.5) * cell;
      const d2 = ((x - cx) ** 2 + (y - cy) ** 2) / (sigma * sigma);
      row.push((200 + 60 * Math.exp(-d2 / 2)).toFixed(2));
    }
    asc += row.join(' ') + '\n';
  }
  const ascPath = join(tmp, 'hill.asc'), tif = join(tmp, 'hill.tif');
  writeFileSync(ascPath, asc);
  execFileSync('gdal_translate', ['-q', '-of', 'GTiff', '-a_srs', 'EPSG:4326', '-ot', 'Float32', ascPath, tif]);
  return tif;
}

test('upload a DEM, follow the terrain, plan, and see the ground profile', async () => {
  await page.click('[data-testid=draw-area]');
  const ring = [[0.4, 0.35], [0.6, 0.35], [0.6, 0.6], [0.4, 0.6]];
  for (const [x, y] of ring) await page.mouse.click(...(await h.mapPoint(page, x, y)));
  await page.mouse.click(...(await h.mapPoint(page, ...ring[0])));
  await page.fill('[data-testid=mission-name]', `e2e terrain ${stamp}`);
  await page.press('[data-testid=mission-name]', 'Tab');
  // saved once without terrain: the field's extent, as the library normalised it
  const name = `e2e terrain ${stamp}`;
  await page.click('[data-testid=mission-save]');
  await page.waitForFunction(async (n) => (await (await fetch(`/api/v1/missions?name=${encodeURIComponent(n)}`)).json()).items.length === 1, name, { timeout: 15000 });
  const { id, bbox } = (await api(`/missions?name=${encodeURIComponent(name)}`)).items[0];
  const tif = hillTiff(bbox);
  // the operator uploads it in the Define tab: it is stored and chosen
  await page.setInputFiles('[data-testid=terrain-upload]', tif);
  await page.waitForFunction(() => document.querySelector('[data-testid=terrain-source]')?.value?.startsWith('dem:'), null, { timeout: 15000 });
  const dems = await api('/dems');
  assert.equal(dems.items.length, 1);
  assert.equal(await page.locator('[data-testid=terrain-follow]').isChecked(), true);
  await page.fill('[data-testid=terrain-tolerance]', '2');
  await page.press('[data-testid=terrain-tolerance]', 'Tab');
  await page.fill('[data-testid=terrain-max-climb]', '2');
  await page.press('[data-testid=terrain-max-climb]', 'Tab');
  await page.click('[data-testid=mission-save]');
  await page.waitForFunction(async (m) => !!(await (await fetch(`/api/v1/missions/${m}`)).json()).mission.terrain, id, { timeout: 15000 });
  const mission = (await api(`/missions/${id}`)).mission;
  assert.deepEqual(mission.terrain, { dem_id: dems.items[0].id, mode: 'follow', tolerance_m: 2, max_climb_mps: 2, max_descent_mps: 2 });
  await h.shot(page, 'terrain-01-define');

  await h.tab(page, 'plan');
  await page.click('[data-testid=plan-start]');
  await page.waitForSelector('[data-testid=plan-state][data-state=done]', { timeout: 180000 });
  await page.waitForSelector('[data-testid=profile-chart][data-samples]', { timeout: 30000 });
  const band = page.locator('[data-testid=profile-band]');
  const lo = Number(await band.getAttribute('data-agl-min'));
  const hi = Number(await band.getAttribute('data-agl-max'));
  const alt = mission.altitude_m ?? 40;
  assert.ok(Math.abs(lo - alt) <= 2.5 && Math.abs(hi - alt) <= 2.5, `above ground ${lo}..${hi} m, asked ${alt} ± 2`);
  assert.match(await band.textContent(), /Above ground over the coverage/);
  await h.planDrawn(page);
  await page.locator('[data-testid=profile-section]').scrollIntoViewIfNeeded();
  await h.shot(page, 'terrain-02-profile');
  await page.setViewportSize({ width: 768, height: 1024 });
  await page.waitForTimeout(400);
  await page.locator('[data-testid=profile-section]').scrollIntoViewIfNeeded();
  await h.shot(page, 'terrain-02-profile-768');
  await page.setViewportSize({ width: 1440, height: 900 });
});
