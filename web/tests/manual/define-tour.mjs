// A manual tour of the Missions and Define tabs with screenshots (not part of the CI tests).
// usage: node tests/manual/define-tour.mjs http://127.0.0.1:PORT OUT_DIR
import { chromium } from 'playwright-core';
import { writeFileSync } from 'node:fs';

const base = process.argv[2] ?? 'http://127.0.0.1:8080';
const out = process.argv[3] ?? '/tmp';
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--no-sandbox', '--headless', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--no-first-run', '--disable-sync'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
const problems = [];
page.on('console', (m) => {
  if (m.type() === 'error' || m.type() === 'warning') problems.push(`${m.type()}: ${m.text()}`);
});
page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
const shot = async (name) => page.screenshot({ path: `${out}/${name}.png` });
const t = (id) => page.getByTestId(id);

await page.goto(`${base}/?tiles=off`);
await t('mission-item').first().waitFor();
await t('mission-item').nth(1).hover();
await shot('01-missions');

// new mission: draw an area and a no-fly zone with clicks
await t('mission-new').click();
await t('draw-area').click();
const map = await page.locator('#map').boundingBox();
const cx = map.x + map.width / 2, cy = map.y + map.height / 2;
for (const [dx, dy] of [[-250, -200], [250, -200], [280, 180], [-230, 200]]) await page.mouse.click(cx + dx, cy + dy);
await page.mouse.click(cx - 250, cy - 200); // close on the first vertex
await page.waitForTimeout(300);
await t('draw-nfz').click();
for (const [dx, dy] of [[-40, -40], [40, -40], [40, 40], [-40, 40]]) await page.mouse.click(cx + dx, cy + dy);
await page.mouse.click(cx - 40, cy - 40);
await page.waitForTimeout(500);
await shot('02-drawn');

// UAVs: one from the catalog, two by hand; shares 50/30/20
await t('uav-add-catalog').selectOption({ index: 1 });
await t('uav-add-manual').click();
await t('uav-add-manual').click();
await t('uav-row').nth(2).waitFor();
const shares = t('uav-share');
for (const [i, v] of [[0, 50], [1, 30], [2, 20]]) {
  await shares.nth(i).fill(String(v));
  await shares.nth(i).press('Enter');
}
// starts: place by clicking, then drag one
for (const [i, dx, dy] of [[0, -300, -230], [1, 300, -230], [2, 0, 240]]) {
  await t('uav-place-start').nth(i).click();
  await page.mouse.click(cx + dx, cy + dy);
}
const st = await page.locator('[data-testid="uav-start"]').nth(2).boundingBox();
await page.mouse.move(st.x + 12, st.y + 12);
await page.mouse.down();
await page.mouse.move(st.x + 80, st.y + 10, { steps: 5 });
await page.mouse.up();
await page.waitForTimeout(500);
await shot('03-uavs');

// camera from the catalog
await t('camera-select').selectOption({ index: 2 });
await t('altitude-input').fill('60');
await t('altitude-input').press('Enter');
await page.waitForTimeout(800);
await t('planner-select').selectOption('boustrophedon');
await page.locator('[data-testid="planner-params"] input').first().fill('30');
await page.locator('[data-testid="planner-params"] input').first().press('Enter');
await t('mission-name').fill('Tour field');
await t('mission-name').press('Enter');
await t('seed-input').fill('7');
await t('seed-input').press('Enter');
await page.waitForTimeout(800);
await shot('04-camera');
await t('mission-save').click();
await page.waitForTimeout(500);
await shot('05-saved');
const state1 = await page.evaluate(() => document.querySelector('[data-testid="mission-status"]').textContent);

// a validation error next to its field
await t('overlap-input').fill('150');
await t('overlap-input').press('Enter');
await page.locator('[data-testid="field-error"]').first().waitFor({ timeout: 3000 });
const fe = await page.locator('[data-testid="field-error"]').first().evaluate((e) => [e.dataset.field, e.textContent]);
await shot('06-error');
await page.keyboard.press('Control+z');
await page.waitForTimeout(600);

// missions list: rename, duplicate, export, delete
await page.getByRole('tab', { name: 'Missions' }).click();
await page.waitForTimeout(400);
const item = t('mission-item').filter({ hasText: 'Tour field' }).first();
await item.getByTestId('mission-rename').click();
await page.getByTestId('mission-rename-input').fill('Tour field renamed');
await page.getByTestId('mission-rename-input').press('Enter');
await page.waitForTimeout(400);
const it2 = t('mission-item').filter({ hasText: 'Tour field renamed' }).first();
await it2.getByTestId('mission-duplicate').click();
await page.waitForTimeout(400);
const [dl] = await Promise.all([page.waitForEvent('download'), it2.getByTestId('mission-export').click()]);
const exported = dl.suggestedFilename();
const copy = t('mission-item').filter({ hasText: '(copy)' }).first();
await copy.getByTestId('mission-delete').click();
await shot('07-confirm-delete');
await page.getByTestId('mission-delete-confirm').click();
await page.waitForTimeout(400);
await shot('08-missions-after');

// import an mCPP file and a GeoJSON file
await t('mission-import-input').setInputFiles(`${process.cwd()}/../examples/mcpp-darp-input.json`);
await page.waitForTimeout(1200);
await shot('09-import-mcpp');
const gj = { type: 'FeatureCollection', features: [
  { type: 'Feature', properties: {}, geometry: { type: 'Polygon', coordinates: [[[22.95, 40.62], [22.96, 40.62], [22.96, 40.628], [22.95, 40.628], [22.95, 40.62]]] } },
  { type: 'Feature', properties: {}, geometry: { type: 'Polygon', coordinates: [[[22.954, 40.623], [22.956, 40.623], [22.956, 40.625], [22.954, 40.625], [22.954, 40.623]]] } },
] };
writeFileSync(`${out}/field.geojson`, JSON.stringify(gj));
await page.getByRole('tab', { name: 'Missions' }).click();
await t('mission-import-input').setInputFiles(`${out}/field.geojson`);
await page.waitForTimeout(1200);
await shot('10-import-geojson');
await page.setViewportSize({ width: 800, height: 1100 });
await page.waitForTimeout(300);
await shot('11-tablet');

console.log(JSON.stringify({ state1, fieldError: fe, exported, problems }, null, 1));
await browser.close();
