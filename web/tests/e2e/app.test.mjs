// End-to-end: the web app in headless Chromium (playwright-core) against the real `uavcover serve`
// with a temporary SQLite database, no tiles (?tiles=off), no mocks. The nine steps, in order,
// with a screenshot of each in $UAVCOVER_WEB_ARTIFACTS (default <repo>/build/web-screenshots), and no
// console error or warning across the run.
//   UAVCOVER_CLI   the uavcover binary (default <repo>/build/uavcover)
// The app must be built first (scripts/build-web → web/dist).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import * as h from './harness.mjs';

const repo = h.repo;
let server, base, browser, page, api;
let consoleProblems = [];
const state = { missionName: `e2e field ${Date.now()}`, missionId: null, planId: null, defineUi: false };

const shot = (name) => h.shot(page, name);
const tab = (name) => h.tab(page, name);
const mapPoint = (fx, fy) => h.mapPoint(page, fx, fy);

before(async () => {
  server = await h.startServer();
  base = server.base;
  api = server.api;
  browser = await h.launchBrowser();
  ({ page, problems: consoleProblems } = await h.openPage(browser));
  await page.goto(`${base}/?tiles=off`);
  await page.waitForSelector('#tabs button[data-tab=plan]');
  await tab('define');
  state.defineUi = (await page.locator('[data-testid=draw-area]').count()) > 0;
});

after(async () => {
  await browser?.close();
  await server?.stop();
});

const needsDefine = (t) => {
  if (!state.defineUi) t.skip('the Missions/Define UI is not in this build');
  return !state.defineUi;
};

test('1. draw an area with mouse clicks, then a no-fly zone', async (t) => {
  if (needsDefine(t)) return;
  await tab('define');
  await page.click('[data-testid=draw-area]');
  const ring = [[0.3, 0.25], [0.75, 0.22], [0.8, 0.75], [0.28, 0.78]];
  for (const [x, y] of ring) await page.mouse.click(...(await mapPoint(x, y)));
  await page.mouse.click(...(await mapPoint(...ring[0]))); // close on the first vertex
  await page.click('[data-testid=draw-nfz]');
  const nfz = [[0.5, 0.45], [0.58, 0.45], [0.58, 0.53], [0.5, 0.53]];
  for (const [x, y] of nfz) await page.mouse.click(...(await mapPoint(x, y)));
  await page.mouse.click(...(await mapPoint(...nfz[0])));
  await page.waitForTimeout(300);
  assert.ok((await page.locator('.leaflet-interactive').count()) >= 0);
  await shot('01-draw-area-nfz');
});

test('2. add 3 UAVs, move one start by dragging, shares 50/30/20', async (t) => {
  if (needsDefine(t)) return;
  const catalog = page.locator('[data-testid=uav-add-catalog]');
  // a new mission starts with one UAV (issue 29): two more from the catalog
  assert.equal(await page.locator('[data-testid=uav-row]').count(), 1);
  for (let i = 0; i < 2; i++) {
    const options = await catalog.locator('option').evaluateAll((os) => os.map((o) => o.value).filter((v) => v));
    await catalog.selectOption(options[0]);
  }
  await page.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length === 3);
  const rows = page.locator('[data-testid=uav-row]');
  const starts = [[0.32, 0.3], [0.7, 0.3], [0.5, 0.7]];
  for (let i = 0; i < 3; i++) {
    await rows.nth(i).locator('[data-testid=uav-place-start]').click();
    await page.mouse.click(...(await mapPoint(...starts[i])));
  }
  // drag the first start marker somewhere else
  const [sx, sy] = await mapPoint(...starts[0]);
  await page.mouse.move(sx, sy);
  await page.mouse.down();
  await page.mouse.move(sx + 30, sy + 20, { steps: 8 });
  await page.mouse.up();
  const shares = [50, 30, 20];
  for (let i = 0; i < 3; i++) {
    await rows.nth(i).locator('[data-testid=uav-share]').fill(String(shares[i]));
    await rows.nth(i).locator('[data-testid=uav-share]').press('Tab');
  }
  for (let i = 0; i < 3; i++) assert.equal(Number(await rows.nth(i).locator('[data-testid=uav-share]').inputValue()), shares[i]);
  await page.fill('[data-testid=mission-name]', state.missionName);
  await page.click('[data-testid=mission-save]');
  await page.waitForFunction(
    async (name) => {
      const r = await fetch(`/api/v1/missions?name=${encodeURIComponent(name)}`);
      return (await r.json()).items.length === 1;
    },
    state.missionName,
    { timeout: 10000 },
  );
  const found = await api(`/missions?name=${encodeURIComponent(state.missionName)}`);
  state.missionId = found.items[0].id;
  const stored = await api(`/missions/${state.missionId}`);
  assert.equal(stored.mission.uavs.length, 3);
  assert.ok(stored.mission.no_fly_zones.length >= 1);
  await shot('02-uavs-shares');
});

test('3. plan, and see 3 regions and 3 paths', async () => {
  if (!state.defineUi) {
    // the seeded example with three UAVs, opened by link
    const list = await api('/missions?name=olive');
    state.missionId = list.items[0].id;
    await page.goto(`${base}/?tiles=off&mission=${state.missionId}`);
  }
  await tab('plan');
  await page.click('[data-testid=plan-start]');
  await page.waitForSelector('[data-testid=plan-progress]');
  await page.waitForSelector('[data-testid=plan-state][data-state=done]', { timeout: 90000 });
  await page.waitForSelector('[data-testid=metrics-panel]');
  const items = page.locator('[data-testid=plan-legend-item]');
  assert.equal(await items.count(), 3);
  for (let i = 0; i < 3; i++) {
    assert.ok(Number(await items.nth(i).getAttribute('data-regions')) >= 1);
    assert.ok(Number(await items.nth(i).getAttribute('data-paths')) >= 1);
  }
  state.planId = Number(await page.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  const plan = await api(`/plans/${state.planId}/plan.json`);
  assert.equal(plan.uavs.length, 3);
  for (const u of plan.uavs) assert.equal(u.region.type, 'MultiPolygon');
  await shot('03-plan');
  // the heatmap overlay over the map
  await page.check('[data-testid=heatmap-toggle]');
  await page.waitForFunction(() => {
    const img = document.querySelector('img.plan-heatmap');
    return img && img.complete && img.naturalWidth > 0;
  });
  await shot('03b-heatmap');
  await page.uncheck('[data-testid=heatmap-toggle]');
  assert.equal(await page.locator('img.plan-heatmap').count(), 0);
});

test('4. the metrics panel matches GET /plans/{id}', async () => {
  const job = await api(`/plans/${state.planId}`);
  assert.equal(job.state, 'done');
  for (const name of ['poc', 'pooc', 'turns', 'length_m', 'flight_time_min', 'total_time_min', 'cost_eur']) {
    const cell = page.locator(`[data-testid=metric-${name}]`);
    assert.equal(Number(await cell.getAttribute('data-value')), job.metrics[name], name);
    assert.notEqual((await cell.innerText()).trim(), '—', name);
  }
  for (const u of job.result.uavs) {
    for (const name of ['turns', 'length_m']) {
      const v = await page.locator(`[data-testid=metrics-panel] td[data-uav="${u.id}"][data-metric=${name}]`).getAttribute('data-value');
      assert.equal(Number(v), u[name], `${u.id} ${name}`);
    }
  }
  await page.locator('[data-testid=metrics-panel]').scrollIntoViewIfNeeded();
  await shot('04-metrics');
});

test('5. download the QGC export and parse it', async () => {
  const uav = (await api(`/plans/${state.planId}`)).result.uavs[0].id;
  const [download] = await Promise.all([
    page.waitForEvent('download'),
    page.click(`[data-testid=export-qgc][data-uav="${uav}"]`),
  ]);
  const qgc = JSON.parse(readFileSync(await download.path(), 'utf8'));
  assert.equal(qgc.fileType, 'Plan');
  assert.ok(Array.isArray(qgc.mission.items) && qgc.mission.items.length > 0);
  assert.match(download.suggestedFilename(), /\.plan$/);
  // and every export as one zip
  const [zip] = await Promise.all([page.waitForEvent('download', { timeout: 30000 }), page.click('[data-testid=export-zip]')]);
  const bytes = readFileSync(await zip.path());
  assert.equal(bytes.readUInt32LE(0), 0x04034b50);
  assert.match(zip.suggestedFilename(), /\.zip$/);
  await page.locator('[data-testid=export-status]').scrollIntoViewIfNeeded();
  await shot('05-exports');
});

test('6. reload: the mission is still there', async () => {
  await page.reload();
  await page.waitForSelector('#tabs button[data-tab=missions]');
  if (state.defineUi) {
    await tab('missions');
    const item = page.locator(`[data-testid=mission-item][data-id="${state.missionId}"]`);
    await item.waitFor();
    assert.match(await item.innerText(), new RegExp(state.missionName));
    await item.click();
    await tab('define');
    await page.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length === 3);
  } else {
    const m = await api(`/missions/${state.missionId}`);
    assert.equal(m.id, state.missionId);
    await tab('plan');
    await page.waitForSelector('[data-testid=plan-mission]');
    assert.match(await page.locator('[data-testid=plan-mission]').innerText(), new RegExp(`#${state.missionId}`));
  }
  await shot('06-reload');
});

test('7. compare two planners (darp, boustrophedon)', async () => {
  await tab('plan');
  await page.click('[data-testid=compare-section] > summary');
  await page.waitForSelector('[data-testid=compare-planner][data-planner=boustrophedon]');
  for (const cb of await page.locator('[data-testid=compare-planner]').all()) {
    const name = await cb.getAttribute('data-planner');
    await cb.setChecked(name === 'darp' || name === 'boustrophedon');
  }
  await page.click('[data-testid=compare-start]');
  await page.waitForSelector('[data-testid=compare-table]', { timeout: 120000 });
  const planners = await page.locator("[data-testid=compare-table] thead th[data-planner]").evaluateAll((rs) => rs.map((r) => r.dataset.planner).sort());
  assert.deepEqual(planners, ['boustrophedon', 'darp']);
  await page.locator('[data-testid=compare-table]').scrollIntoViewIfNeeded();
  await shot('07-compare-table');
  await page.waitForSelector('[data-testid=compare-side-by-side]:not([disabled])', { timeout: 120000 });
  await page.click('[data-testid=compare-side-by-side]');
  await page.waitForSelector('[data-testid=compare-maps] .plan-overlay-map');
  assert.equal(await page.locator('[data-testid=compare-maps] .plan-overlay-map').count(), 2);
  // synchronised: zooming one map zooms the other
  const maps = page.locator('[data-testid=compare-maps] .plan-overlay-map');
  const scale = (i) => maps.nth(i).locator('.leaflet-control-scale-line').innerText();
  const before = await scale(1);
  await maps.nth(0).locator('.leaflet-control-zoom-in').click();
  await page.waitForFunction((b) => document.querySelectorAll('[data-testid=compare-maps] .leaflet-control-scale-line')[1].textContent !== b, before);
  await page.waitForTimeout(400);
  await shot('07b-compare-maps');
  await page.click('[data-testid=compare-close]');
  assert.equal(await page.locator('[data-testid=compare-maps]').count(), 0);
});

test('8. import an mCPP file', async (t) => {
  if (needsDefine(t)) return;
  await tab('missions');
  const before = (await api('/missions?limit=200')).items.length;
  await page.setInputFiles('[data-testid=mission-import-input]', join(repo, 'examples/mcpp-darp-input.json'));
  await page.waitForFunction(
    async (n) => (await (await fetch('/api/v1/missions?limit=200')).json()).items.length === n + 1,
    before,
    { timeout: 10000 },
  );
  await page.waitForFunction((n) => document.querySelectorAll('[data-testid=mission-item]').length >= n + 1, before);
  await shot('08-import-mcpp');
});

test('9. a validation error next to its field', async (t) => {
  if (needsDefine(t)) return;
  await tab('define');
  await page.fill('[data-testid=altitude-input]', '-5');
  await page.press('[data-testid=altitude-input]', 'Tab');
  const err = page.locator('[data-testid=field-error][data-field=altitude_m]');
  await err.waitFor({ timeout: 10000 });
  assert.match(await err.innerText(), /altitude/i);
  // next to its field: the error box is close below or beside the input
  const a = await page.locator('[data-testid=altitude-input]').boundingBox();
  const b = await err.boundingBox();
  assert.ok(Math.abs(b.y - (a.y + a.height)) < 60 || Math.abs(b.y - a.y) < 30, 'the error sits by the altitude field');
  await shot('09-validation-error');
});

test('no console errors or warnings', () => {
  assert.deepEqual(consoleProblems, []);
});
