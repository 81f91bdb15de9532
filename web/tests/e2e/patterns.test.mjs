// End-to-end: the Define tab's Pattern section (docs/patterns.md, issue 30) in headless Chromium against
// the real `uavcover serve`: draw a corridor's centre line with mouse clicks, give its width and the
// pattern options, save, plan with the boustrophedon planner and see the plan drawn; the stored mission
// and the plan have the corridor's lanes.
//   UAVCOVER_CLI   the uavcover binary (default <repo>/build/uavcover)
// The app must be built first (scripts/build-web → web/dist).
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import * as h from './harness.mjs';

let server, browser, page, api;
let consoleProblems = [];
const name = `e2e corridor ${Date.now()}`;
let missionId = null;

before(async () => {
  server = await h.startServer();
  api = server.api;
  browser = await h.launchBrowser();
  ({ page, problems: consoleProblems } = await h.openPage(browser));
  await page.goto(`${server.base}/?tiles=off`);
  await page.waitForSelector('#tabs button[data-tab=plan]');
  await h.tab(page, 'define');
});

after(async () => {
  await browser?.close();
  await server?.stop();
});

test('1. draw a corridor line, set its width and the pattern options, save', async () => {
  await page.selectOption('[data-testid=pattern-kind]', 'corridor');
  await page.click('[data-testid=draw-corridor]');
  const line = [[0.25, 0.6], [0.5, 0.45], [0.75, 0.55]];
  for (const [x, y] of line) await page.mouse.click(...(await h.mapPoint(page, x, y)));
  await page.mouse.click(...(await h.mapPoint(page, ...line[line.length - 1]))); // finish on the last vertex
  await page.waitForFunction(() => document.querySelector('[data-testid=corridor-info]')?.textContent?.includes('3 vertices'));
  await page.fill('[data-testid=corridor-width]', '80');
  await page.press('[data-testid=corridor-width]', 'Tab');
  await page.check('[data-testid=pattern-crosshatch]');
  await page.fill('[data-testid=pattern-turnaround_m]', '10');
  await page.press('[data-testid=pattern-turnaround_m]', 'Tab');
  await page.selectOption('[data-testid=pattern-entry]', 'sw');
  await page.selectOption('[data-testid=planner-select]', 'boustrophedon');
  await page.fill('[data-testid=mission-name]', name);
  await page.click('[data-testid=mission-save]');
  await page.waitForFunction(
    async (n) => (await (await fetch(`/api/v1/missions?name=${encodeURIComponent(n)}`)).json()).items.length === 1,
    name,
    { timeout: 15000 },
  );
  missionId = (await api(`/missions?name=${encodeURIComponent(name)}`)).items[0].id;
  const stored = (await api(`/missions/${missionId}`)).mission;
  assert.equal(stored.area, undefined);
  assert.equal(stored.corridor.line.type, 'LineString');
  assert.equal(stored.corridor.line.coordinates.length, 3);
  assert.equal(stored.corridor.width_m, 80);
  assert.equal(stored.pattern.crosshatch, true);
  assert.equal(stored.pattern.turnaround_m, 10);
  assert.equal(stored.pattern.entry, 'sw');
  await h.shot(page, 'patterns-01-corridor');
});

test('2. plan it: the result is drawn and its coverage follows the corridor', async () => {
  await h.tab(page, 'plan');
  await page.click('[data-testid=plan-start]');
  await page.waitForSelector('[data-testid=plan-state][data-state=done]', { timeout: 120000 });
  await page.waitForSelector('[data-testid=metrics-panel]');
  const items = page.locator('[data-testid=plan-legend-item]');
  assert.ok((await items.count()) >= 1);
  assert.ok(Number(await items.nth(0).getAttribute('data-paths')) >= 1);
  const planId = Number(await page.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  const paths = await api(`/plans/${planId}/paths.geojson`);
  const coverage = paths.features.filter((f) => f.properties.kind === 'coverage');
  assert.ok(coverage.length >= 1);
  // turns and turnarounds flown with the camera off are marked on the coverage parts
  assert.ok(coverage.some((f) => Array.isArray(f.properties.camera_off) && f.properties.camera_off.length > 0));
  const plan = await api(`/plans/${planId}/plan.json`);
  assert.equal(plan.mission.corridor.width_m, 80);
  await h.shot(page, 'patterns-02-plan');
});

test('no console errors or warnings', () => {
  assert.deepEqual(consoleProblems, []);
});
