// End-to-end, issue 31: terrain in the web app against the real `uavcover serve`. The operator draws a
// field, uploads a GeoTIFF elevation model (written by GDAL's own gdal_translate in the test) in the
// Define tab, turns terrain following on with a tolerance and a climb limit, plans, and sees the ground
// profile under each UAV's path with its band of heights above ground; screenshots at 1440x900 and
// 768x1024. Then the export options: the .waypoints in ArduPilot's terrain frame, and the .plan split to
// the vehicle's item capacity (a zip of whole missions). Last the field options: rally points placed on
// the map (one removed with a right-click), planned, drawn on the plan map with each UAV's geofence, and
// in the .plan export.
//   UAVCOVER_CLI   the uavcover binary (default <repo>/build/uavcover)
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
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

/** A screenshot at 768x1024 with `selector` scrolled into view, then back to 1440x900. */
async function shotAt768(name, selector) {
  await page.setViewportSize({ width: 768, height: 1024 });
  await page.waitForTimeout(400);
  await page.locator(selector).scrollIntoViewIfNeeded();
  await h.shot(page, name);
  await page.setViewportSize({ width: 1440, height: 900 });
}

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
  await shotAt768('terrain-02-profile-768', '[data-testid=profile-section]');
});

test('the trajectory of each UAV against time, by either method (issue 33)', async () => {
  // closed until opened: nothing is asked of the server before
  const section = page.locator('[data-testid=trajectory-section]');
  assert.equal(await section.evaluate((d) => d.open), false);
  await section.locator('summary').click();
  const plot = page.locator('[data-testid=trajectory-plot]');
  const loaded = (method) =>
    page.waitForFunction(
      (m) => {
        const img = document.querySelector('[data-testid=trajectory-plot]');
        return img && !img.hidden && img.dataset.method === m && img.complete && img.naturalWidth > 0;
      },
      method,
      { timeout: 60000 },
    );
  await loaded('fillet-lines');
  const uavs = await page.locator('[data-testid=trajectory-uav] option').evaluateAll((os) => os.map((o) => o.value));
  assert.ok(uavs.length >= 1, 'a UAV to choose');
  assert.equal(await plot.getAttribute('data-uav'), uavs[0]);
  const size = await plot.evaluate((i) => [i.naturalWidth, i.naturalHeight]);
  assert.ok(size[0] >= 400 && size[1] >= 300, `a plot of ${size}`);
  assert.match(await page.locator('[data-testid=trajectory-note]').textContent(), /position, velocity and acceleration/);
  await page.selectOption('[data-testid=trajectory-method]', 'polynomial');
  await loaded('polynomial');
  if (uavs.length > 1) {
    await page.selectOption('[data-testid=trajectory-uav]', uavs[1]);
    await page.waitForFunction((u) => document.querySelector('[data-testid=trajectory-plot]')?.dataset.uav === u, uavs[1], { timeout: 60000 });
    await loaded('polynomial');
  }
  await section.scrollIntoViewIfNeeded();
  await h.shot(page, 'terrain-02b-trajectory');
  await shotAt768('terrain-02b-trajectory-768', '[data-testid=trajectory-section]');
  // Enlarge: the same plot over the page, as large as the window lets it (the panel's is ~320 px wide)
  await page.click('[data-testid=trajectory-enlarge]');
  const big = page.locator('[data-testid=trajectory-plot-big]');
  await page.waitForFunction(() => {
    const i = document.querySelector('[data-testid=trajectory-plot-big]');
    return i && i.complete && i.naturalWidth > 0;
  });
  const [small, large, natural] = [await plot.evaluate((i) => i.clientWidth), await big.evaluate((i) => i.clientWidth), await big.evaluate((i) => i.naturalWidth)];
  assert.ok(large > 1.5 * small, `enlarged ${large} px against ${small} px in the panel`);
  assert.ok(large <= natural + 1, 'never drawn larger than it was made');
  assert.equal(await big.getAttribute('src'), await plot.getAttribute('src'), 'the same plot, not a second request');
  await h.shot(page, 'terrain-02c-trajectory-enlarged');
  await page.keyboard.press('Escape');
  assert.equal(await page.locator('[data-testid=trajectory-enlarged]').count(), 0, 'Escape closes it');
});

test('export for ArduPilot in the terrain frame, and split to the item capacity', async () => {
  const planId = Number(await page.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  assert.ok(planId > 0, 'the plan tab names its plan');
  const uav = (await api(`/plans/${planId}`)).result.uavs[0].id;
  await page.locator('[data-testid=exports-panel]').scrollIntoViewIfNeeded();
  await page.selectOption('[data-testid=export-autopilot]', 'ardupilot');
  await page.check('[data-testid=export-terrain-frame]');
  const [wpl] = await Promise.all([page.waitForEvent('download'), page.click(`[data-testid=export-wpl][data-uav="${uav}"]`)]);
  const rows = readFileSync(await wpl.path(), 'utf8').trim().split('\n');
  assert.equal(rows[0], 'QGC WPL 110');
  const terrain = rows.slice(1).map((r) => r.split('\t').map(Number)).filter((v) => v[2] === 10);
  assert.ok(terrain.length > 4, `${terrain.length} waypoints in MAV_FRAME_GLOBAL_TERRAIN_ALT`);
  for (const v of terrain) assert.ok(Math.abs(v[10] - 40) < 1e-3, `terrain-frame height ${v[10]}`);
  // the terrain frame is ArduPilot's: the PX4 export refuses it, in words
  await page.selectOption('[data-testid=export-autopilot]', 'px4');
  await page.click(`[data-testid=export-qgc][data-uav="${uav}"]`);
  await page.waitForFunction(() => /ArduPilot/.test(document.querySelector('[data-testid=export-status]')?.textContent ?? ''), null, { timeout: 15000 });
  await h.shot(page, 'terrain-03-export-refused');
  await page.uncheck('[data-testid=export-terrain-frame]');
  await page.selectOption('[data-testid=export-autopilot]', '');
  await page.check('[data-testid=export-split]');
  const [zip] = await Promise.all([page.waitForEvent('download'), page.click(`[data-testid=export-qgc][data-uav="${uav}"]`)]);
  assert.equal(zip.suggestedFilename(), `${uav}.plan.zip`);
  const bytes = readFileSync(await zip.path());
  assert.equal(bytes.readUInt32LE(0), 0x04034b50, 'a zip');
  const listing = execFileSync('unzip', ['-Z1', await zip.path()], { encoding: 'utf8' }).trim().split('\n')
    .sort((a, b) => Number(a.match(/\.s(\d+)\./)?.[1]) - Number(b.match(/\.s(\d+)\./)?.[1]));
  // its battery sorties, each a whole mission within the PX4 capacity
  assert.ok(listing.length >= 1 && listing.every((n, k) => n === `${uav}.s${k + 1}.plan`), listing.join(', '));
  for (const name of listing) {
    const part = JSON.parse(execFileSync('unzip', ['-p', await zip.path(), name], { encoding: 'utf8' }));
    assert.equal(part.fileType, 'Plan');
    assert.ok(part.mission.items.length <= 500 && part.mission.items[0].command === 22, name);
  }
  await h.shot(page, 'terrain-04-export-options');
});

test('place rally points on the map, plan, and see them with the geofence', async () => {
  await h.tab(page, 'define');
  for (const [x, y] of [[0.5, 0.45], [0.45, 0.52]]) {
    await page.click('[data-testid=rally-add]');
    await page.mouse.click(...(await h.mapPoint(page, x, y)));
  }
  await page.waitForFunction(() => document.querySelectorAll('[data-testid=rally-point]').length === 2, null, { timeout: 10000 });
  assert.equal(await page.textContent('[data-testid=rally-count]'), '2 given');
  await page.click('[data-testid=rally-point] >> nth=1', { button: 'right' });
  await page.waitForFunction(() => document.querySelectorAll('[data-testid=rally-point]').length === 1, null, { timeout: 10000 });
  await h.shot(page, 'terrain-05-rally-define');
  await page.click('[data-testid=mission-save]');
  const name = `e2e terrain ${stamp}`;
  const { id } = (await api(`/missions?name=${encodeURIComponent(name)}`)).items[0];
  await page.waitForFunction(async (m) => ((await (await fetch(`/api/v1/missions/${m}`)).json()).mission.rally ?? []).length === 1, id, { timeout: 15000 });
  const [point] = (await api(`/missions/${id}`)).mission.rally;

  await h.tab(page, 'plan');
  const before = Number(await page.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  await page.click('[data-testid=plan-start]');
  await page.waitForFunction((b) => Number(document.querySelector('[data-testid=metrics-panel]')?.getAttribute('data-plan-id')) > b, before, { timeout: 180000 });
  const planId = Number(await page.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  await page.waitForFunction(() => document.querySelectorAll('#map .plan-rally').length === 1, null, { timeout: 15000 });
  await page.check('[data-testid=fence-toggle]');
  await page.waitForFunction(() => Number(document.querySelector('[data-testid=fence-note]')?.dataset.polygons) >= 1, null, { timeout: 30000 });
  assert.ok((await page.locator('#map .plan-fence').count()) >= 1, 'the geofence is drawn');
  await h.planDrawn(page);
  await h.shot(page, 'terrain-06-rally-fence');
  await shotAt768('terrain-06-rally-fence-768', '[data-testid=exports-panel]');
  // the .plan carries the rally point and the fence the map shows
  const uav = (await api(`/plans/${planId}`)).result.uavs[0].id;
  const qgc = await api(`/plans/${planId}/exports/qgc?uav=${encodeURIComponent(uav)}`);
  assert.equal(qgc.rallyPoints.points.length, 1);
  assert.ok(Math.abs(qgc.rallyPoints.points[0][0] - point[1]) < 1e-7 && Math.abs(qgc.rallyPoints.points[0][1] - point[0]) < 1e-7);
  assert.equal(qgc.geoFence.polygons.filter((p) => p.inclusion).length, 1);
  // leaving the tab takes them off the map; coming back draws them again
  await h.tab(page, 'define');
  assert.equal(await page.locator('#map .plan-rally').count(), 0);
  await h.tab(page, 'plan');
  await page.waitForFunction(() => document.querySelectorAll('#map .plan-fence').length >= 1 && document.querySelectorAll('#map .plan-rally').length === 1, null, { timeout: 15000 });
});
