// Manual check: drawing keys (Ctrl-Z, Esc, Delete), cutting a hole, KML import, a bad file, search.
// usage: node tests/manual/define-keys.mjs BASE_URL OUT_DIR (against a fresh database seeded with examples/)
import { chromium } from 'playwright-core';
import { writeFileSync } from 'node:fs';
const base = process.argv[2], out = process.argv[3];
const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--no-sandbox', '--headless', '--disable-gpu'] });
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const problems = [];
page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') problems.push(`${m.type()}: ${m.text()}`); });
page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
const t = (id) => page.getByTestId(id);
const info = () => page.locator('.define-section p.define-small').first().textContent();
const log = [];
await page.goto(`${base}/?tiles=off`);
await t('mission-item').filter({ hasText: 'North olive grove' }).getByTestId('mission-open').click();
await page.waitForTimeout(800);
log.push(['opened', await info(), await t('spacing-value').textContent(), await t('footprint-value').textContent(), await t('camera-select').inputValue()]);
const map = await page.locator('#map').boundingBox();
const cx = map.x + map.width / 2, cy = map.y + map.height / 2;
// draw: 3 clicks, ctrl-z, esc
await t('draw-area').click();
await page.mouse.click(cx + 300, cy + 250);
await page.mouse.click(cx + 350, cy + 250);
await page.mouse.click(cx + 350, cy + 300);
const before = await page.evaluate(() => document.querySelectorAll('.marker-icon').length);
await page.keyboard.press('Control+z');
const after = await page.evaluate(() => document.querySelectorAll('.marker-icon').length);
log.push(['ctrl-z while drawing: vertex markers', before, after]);
await page.keyboard.press('Escape');
await page.waitForTimeout(200);
log.push(['after esc', await info(), await t('draw-area').getAttribute('class')]);
// delete a vertex of the area: the first vertex marker of the area
const markers = page.locator('.leaflet-marker-icon.marker-icon:not(.marker-icon-middle)');
const n0 = await markers.count();
await markers.first().click();
await page.keyboard.press('Delete');
await page.waitForTimeout(300);
const n1 = await markers.count();
log.push(['delete vertex: markers', n0, n1, await info()]);
await page.keyboard.press('Control+z');
await page.waitForTimeout(300);
log.push(['undo: markers', await markers.count(), await info()]);
// click inside the first NFZ and delete it
const nfzCentre = await page.evaluate(() => null);
// cut a hole
await t('draw-hole').click();
for (const [dx, dy] of [[-200, 80], [-150, 80], [-150, 130], [-200, 130]]) await page.mouse.click(cx + dx, cy + dy);
await page.mouse.click(cx - 200, cy + 80);
await page.waitForTimeout(500);
log.push(['after cut', await info()]);
await page.screenshot({ path: `${out}/k1-cut.png` });
// select the hole's area polygon by clicking on it (area), then delete → whole polygon goes
// instead: click on an NFZ
writeFileSync(`${out}/k.kml`, `<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document>
<Placemark><name>Field</name><Polygon><outerBoundaryIs><LinearRing><coordinates>22.97,40.63,0 22.98,40.63,0 22.98,40.64,0 22.97,40.64,0 22.97,40.63,0</coordinates></LinearRing></outerBoundaryIs>
<innerBoundaryIs><LinearRing><coordinates>22.972,40.632 22.974,40.632 22.974,40.634 22.972,40.634 22.972,40.632</coordinates></LinearRing></innerBoundaryIs></Polygon></Placemark>
<Placemark><name>No fly: mast</name><Polygon><outerBoundaryIs><LinearRing><coordinates>22.976,40.636 22.977,40.636 22.977,40.637 22.976,40.637</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
</Document></kml>`);
await page.getByRole('tab', { name: 'Missions' }).click();
await t('mission-import-input').setInputFiles(`${out}/k.kml`);
await page.waitForTimeout(1000);
log.push(['kml', await info(), await t('mission-name').inputValue()]);
// click in the middle of the nfz → select → Delete
const box = await page.locator('#map').boundingBox();
await page.screenshot({ path: `${out}/k2-kml.png` });
// bad file
writeFileSync(`${out}/bad.json`, '{"hello": 1}');
await page.getByRole('tab', { name: 'Missions' }).click();
await t('mission-import-input').setInputFiles(`${out}/bad.json`);
await page.waitForTimeout(500);
log.push(['bad', await page.locator('.missions-status').textContent()]);
// search
await t('mission-search').fill('olive');
await page.waitForTimeout(800);
log.push(['search', await t('mission-item').count()]);
console.log(JSON.stringify({ log, problems }, null, 1));
await browser.close();
