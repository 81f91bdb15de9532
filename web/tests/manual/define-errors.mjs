// Manual check: vertex drag, zone delete/undo, server errors next to shares, planner parameters and UAV ids, save refused then saved, camera modes, tablet size.
// usage: node tests/manual/define-errors.mjs BASE_URL OUT_DIR (against a fresh database seeded with examples/)
import { chromium } from 'playwright-core';
const base = process.argv[2], out = process.argv[3];
const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--no-sandbox', '--headless', '--disable-gpu'] });
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const problems = [];
page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') problems.push(`${m.type()}: ${m.text()}`); });
page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
const t = (id) => page.getByTestId(id);
const info = () => page.locator('.define-section p.define-small').first().textContent();
const errs = () => page.locator('[data-testid=field-error]').evaluateAll((es) => es.map((e) => [e.dataset.field, e.textContent, e.parentElement.className]));
const log = [];
await page.goto(`${base}/?tiles=off`);
await t('mission-item').filter({ hasText: 'imported mCPP' }).first().getByTestId('mission-open').click();
await page.waitForTimeout(800);
const map = await page.locator('#map').boundingBox();
// drag the first area vertex
const mk = page.locator('.leaflet-marker-icon.marker-icon:not(.marker-icon-middle)').first();
const b = await mk.boundingBox();
await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2);
await page.mouse.down();
await page.mouse.move(b.x + 60, b.y + 40, { steps: 6 });
await page.mouse.up();
await page.waitForTimeout(500);
log.push(['dragged vertex; status', await t('mission-status').textContent()]);
// click the nfz centre, delete
const cx = map.x + map.width / 2, cy = map.y + map.height / 2;
await page.mouse.click(cx, cy + 10);
await page.keyboard.press('Delete');
await page.waitForTimeout(300);
log.push(['deleted nfz?', await info()]);
await page.keyboard.press('Control+z');
await page.waitForTimeout(300);
log.push(['undo', await info()]);
// share 100 → the other 0 → server error
await t('uav-share').nth(0).fill('100');
await t('uav-share').nth(0).press('Enter');
await page.waitForTimeout(900);
log.push(['share 100', await errs(), await t('general-error').isVisible()]);
await page.screenshot({ path: `${out}/m1-share-error.png` });
await page.keyboard.press('Control+z'); // focus is in the input: ignored by design
await t('uav-share').nth(0).fill('70');
await t('uav-share').nth(0).press('Enter');
await page.waitForTimeout(900);
log.push(['share 70', await errs(), await t('uav-share').nth(1).inputValue()]);
// planner param error
await page.locator('[data-testid=planner-params] input[data-param=max_iterations]').fill('0');
await page.locator('[data-testid=planner-params] input[data-param=max_iterations]').press('Enter');
await page.waitForTimeout(900);
log.push(['param 0', await errs()]);
await page.locator('[data-testid=planner-params] input[data-param=max_iterations]').fill('');
await page.locator('[data-testid=planner-params] input[data-param=max_iterations]').press('Enter');
// bad uav id
await t('uav-id').nth(1).fill('bad id');
await t('uav-id').nth(1).press('Enter');
await page.waitForTimeout(900);
log.push(['bad id', await errs()]);
await page.screenshot({ path: `${out}/m2-id-error.png` });
// save with the error: refused, shown at the field
await t('mission-save').click();
await page.waitForTimeout(500);
log.push(['save refused', await t('mission-status').textContent(), await errs()]);
await t('uav-id').nth(1).fill('b2');
await t('uav-id').nth(1).press('Enter');
await page.waitForTimeout(600);
await t('mission-save').click();
await page.waitForTimeout(500);
log.push(['saved', await t('mission-status').textContent(), await errs()]);
// camera: switch to the paper convention and back to none
await t('camera-select').selectOption('paper');
await page.waitForTimeout(800);
log.push(['paper', await t('spacing-value').textContent(), await t('footprint-value').textContent(), await t('overlap-input').inputValue()]);
await t('camera-select').selectOption('cat:3');
await page.waitForTimeout(800);
log.push(['cat3', await t('spacing-value').textContent(), await t('gsd-value').textContent()]);
await page.setViewportSize({ width: 768, height: 1024 });
await page.waitForTimeout(300);
await page.screenshot({ path: `${out}/m3-tablet.png` });
console.log(JSON.stringify({ log, problems }, null, 1));
await browser.close();
