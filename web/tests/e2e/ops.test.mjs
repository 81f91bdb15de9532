// The web app for real operations (issue 29): one browser test per defect of the issue, against the real
// `uavcover serve` (temporary SQLite, seeded, tiles off, no mocks), and screenshots of every tab at
// 1440x900 and 768x1024 (ops-*.png in $UAVCOVER_WEB_ARTIFACTS).
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import * as h from './harness.mjs';

let server, browser;
const problems = [];
const olive = JSON.parse(readFileSync(join(h.repo, 'examples/olive-grove.json'), 'utf8'));

before(async () => {
  server = await h.startServer();
  browser = await h.launchBrowser();
});

after(async () => {
  await browser?.close();
  await server?.stop();
});

async function page(size) {
  const p = await h.openPage(browser, size);
  problems.push(p.problems);
  return p.page;
}

const post = (path, body) => server.api(path, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });

/** A small field (300 m x 200 m at 40.6 N) as a uavcover v1 document. */
function smallField(name, extra = {}) {
  const lon0 = 22.95, lat0 = 40.6, mlat = 1 / 111320, mlon = mlat / Math.cos((lat0 * Math.PI) / 180);
  const at = (x, y) => [lon0 + x * mlon, lat0 + y * mlat];
  return {
    name,
    area: { type: 'Polygon', coordinates: [[at(0, 0), at(300, 0), at(300, 200), at(0, 200), at(0, 0)]] },
    spacing_m: 20,
    altitude_m: 30,
    uavs: [
      { id: 'A', start: at(20, -20), speed_mps: 8 },
      { id: 'B', start: at(120, -20), speed_mps: 8 },
    ],
    planner: 'darp',
    seed: 3,
    ...extra,
  };
}

async function waitJob(path) {
  for (;;) {
    const j = await server.api(path);
    if (['done', 'failed', 'cancelled'].includes(j.state)) return j;
    await new Promise((r) => setTimeout(r, 200));
  }
}

async function planned(missionId, body = {}) {
  const j = await post(`/missions/${missionId}/plans`, body);
  const done = await waitJob(`/plans/${j.id}`);
  assert.equal(done.state, 'done', JSON.stringify(done.error));
  return done;
}

async function openMission(p, id, hash = 'define') {
  await p.goto(`${server.base}/?tiles=off&mission=${id}#${hash}`);
  await p.waitForSelector('#tabs button[aria-selected=true]');
}

/** A flight of real vehicles (a port nobody answers on): it stays "created", not ended, without a fleet. */
async function idleFlight(plan) {
  const uavs = plan.result.uavs.map((u) => u.id);
  return post(`/plans/${plan.id}/flights`, { vehicles: uavs.map((uav, i) => ({ uav, endpoint: 'udp:127.0.0.1:9', sysid: i + 1 })) });
}

test('defect 1: a flight that has not ended stays reachable and shown when the mission gets a newer plan', async () => {
  const m = await post('/missions', smallField('ops flight kept'));
  const first = await planned(m.id);
  const flight = await idleFlight(first);
  const second = await planned(m.id);
  assert.ok(second.id > first.id);

  // a reload after the newer plan: the Fly tab follows the flight of plan #1, marked, and says so
  const p = await page();
  await openMission(p, m.id, 'fly');
  const row = p.locator(`[data-testid=fly-active-flight][data-id="${flight.id}"]`);
  await row.waitFor({ timeout: 20000 });
  assert.equal(await row.getAttribute('data-plan'), String(first.id));
  await p.waitForFunction((id) => document.querySelector('[data-testid=fly-state]')?.textContent.includes(`Flight #${id}`), flight.id);
  assert.match(await p.locator('[data-testid=fly-plan]').innerText(), new RegExp(`Plan #${first.id}\\b`));
  const note = p.locator('[data-testid=fly-other-plan]');
  await note.waitFor();
  assert.match(await note.innerText(), new RegExp(`open plan is #${second.id}`));
  await h.shot(p, 'ops-1-active-flight');

  // planned again from this page: the flight stays on screen
  await h.tab(p, 'plan');
  await p.click('[data-testid=plan-start]');
  await p.waitForSelector('[data-testid=plan-state][data-state=done]', { timeout: 90000 });
  await p.waitForFunction(() => Number(document.querySelector('[data-testid=metrics-panel]')?.dataset.planId) > 0);
  const third = Number(await p.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  assert.ok(third > second.id);
  await h.tab(p, 'fly');
  assert.match(await p.locator('[data-testid=fly-state]').innerText(), new RegExp(`Flight #${flight.id}\\b`));
  await p.waitForFunction((n) => document.querySelector('[data-testid=fly-other-plan]')?.textContent.includes(`#${n}`), third);

  // the newest plan, then back to the flight in one click
  await p.click('[data-testid=fly-open-plan]');
  await p.waitForFunction((n) => document.querySelector('[data-testid=fly-plan]')?.textContent.startsWith(`Plan #${n} `), third);
  assert.ok(await p.locator('.fly-flight').isHidden(), 'no flight of the newest plan is followed');
  await row.locator('[data-testid=fly-active-follow]').click();
  await p.waitForFunction((id) => document.querySelector('[data-testid=fly-state]')?.textContent.includes(`Flight #${id}`), flight.id);
  assert.match(await p.locator('[data-testid=fly-plan]').innerText(), new RegExp(`Plan #${first.id}\\b`));

  // once it ended (aborted), it is no longer listed
  await server.api(`/flights/${flight.id}`, { method: 'DELETE' });
  await p.waitForSelector('[data-testid=fly-state][data-state=aborted]', { timeout: 20000 });
  await p.waitForSelector('[data-testid=fly-active]', { state: 'hidden', timeout: 20000 });
});

test('defect 3: unsaved edits are not dropped without asking (another mission, a reload)', async () => {
  const a = await post('/missions', smallField('ops unsaved A'));
  const b = await post('/missions', smallField('ops unsaved B'));
  const p = await page();
  await openMission(p, a.id);
  await p.waitForFunction(() => document.querySelector('[data-testid=mission-name]')?.value === 'ops unsaved A');
  await p.fill('[data-testid=mission-name]', 'ops unsaved A edited');
  await p.press('[data-testid=mission-name]', 'Tab');
  await p.waitForFunction(() => /unsaved changes/.test(document.querySelector('[data-testid=mission-status]')?.textContent));
  await h.tab(p, 'missions');
  await p.locator(`[data-testid=mission-item][data-id="${b.id}"] [data-testid=mission-open]`).click();
  const dialog = p.locator('[data-testid=discard-dialog]');
  await dialog.waitFor();
  assert.match(await dialog.innerText(), /unsaved changes/);
  await h.shot(p, 'ops-3-unsaved');
  await p.click('[data-testid=discard-cancel]');
  // kept: still the edited mission A, in the Define tab
  await p.waitForSelector('[data-testid=mission-name]:visible');
  assert.equal(await p.locator('[data-testid=mission-name]').inputValue(), 'ops unsaved A edited');
  assert.match(await p.locator('[data-testid=mission-status]').innerText(), new RegExp(`Mission #${a.id}.*unsaved`));

  // a reload asks through the browser (beforeunload); accepted, it reloads
  const kinds = [];
  p.on('dialog', (d) => {
    kinds.push(d.type());
    void d.accept();
  });
  await p.reload();
  assert.deepEqual(kinds, ['beforeunload']);

  // discarding on purpose opens the other mission
  await p.waitForFunction(() => document.querySelector('[data-testid=mission-name]')?.value === 'ops unsaved A');
  await p.fill('[data-testid=mission-name]', 'ops unsaved A again');
  await p.press('[data-testid=mission-name]', 'Tab');
  await h.tab(p, 'missions');
  await p.locator(`[data-testid=mission-item][data-id="${b.id}"] [data-testid=mission-open]`).click();
  await p.click('[data-testid=discard-confirm]');
  await p.waitForFunction(() => document.querySelector('[data-testid=mission-name]')?.value === 'ops unsaved B');
  // nothing unsaved: no question
  await h.tab(p, 'missions');
  await p.locator(`[data-testid=mission-item][data-id="${a.id}"] [data-testid=mission-open]`).click();
  await p.waitForFunction(() => document.querySelector('[data-testid=mission-name]')?.value === 'ops unsaved A');
  assert.equal(await p.locator('[data-testid=discard-dialog]').count(), 0);
});

test('defect 4: catalog UAVs keep their identity across save and reopen; their own camera is used', async () => {
  const cams = (await server.api('/cameras')).items;
  assert.ok(cams.length >= 2, 'the seeded camera catalog');
  const [wide, other] = cams;
  const uav = await post('/uavs', { name: 'ops catalog quad', speed_mps: 9, max_accel_mps2: 3, endurance_min: 31, cost_per_min_eur: 0.05, camera_id: other.id });
  const doc = smallField('ops catalog', { spacing_m: undefined, altitude_m: undefined, camera: { catalog_id: wide.id, altitude_m: 40, side_overlap: 0.6 } });
  delete doc.spacing_m;
  delete doc.altitude_m;
  doc.uavs = [
    { id: 'cat1', catalog_id: uav.id, start: doc.uavs[0].start },
    { id: 'hand', speed_mps: 7, start: doc.uavs[1].start },
  ];
  const m = await post('/missions', doc);
  // the server uses the catalog UAV's camera: its own camera block in the normalised mission
  const stored = await server.api(`/missions/${m.id}`);
  const own = stored.mission.uavs.find((u) => u.id === 'cat1').camera;
  assert.ok(own, JSON.stringify(stored.mission.uavs));
  assert.equal(own.image_width_px, other.image_width_px);
  assert.equal(own.altitude_m, 40);

  const p = await page();
  await openMission(p, m.id);
  const row = p.locator('[data-testid=uav-row][data-id=cat1]');
  await row.waitFor();
  await p.waitForFunction(() => document.querySelector('[data-testid=uav-row][data-id=cat1] .define-uav-cat')?.textContent === 'ops catalog quad');
  assert.equal(await row.locator('[data-testid=uav-speed]').count(), 0, 'not a hand-made row');
  // a new revision keeps the link
  await p.fill('[data-testid=mission-name]', 'ops catalog r2');
  await p.press('[data-testid=mission-name]', 'Tab');
  await p.click('[data-testid=mission-save]');
  await p.waitForFunction(() => /revision 2/.test(document.querySelector('[data-testid=mission-status]')?.textContent));
  const r2 = await server.api(`/missions/${m.id}`);
  assert.equal(r2.revision, 2);
  assert.equal(r2.source.uavs[0].catalog_id, uav.id, JSON.stringify(r2.source.uavs[0]));
  await p.reload();
  await p.waitForFunction(() => document.querySelector('[data-testid=uav-row][data-id=cat1] .define-uav-cat')?.textContent === 'ops catalog quad');
  await h.shot(p, 'ops-4-catalog-uav');
});

test('defects 6 and 9: grouped, rounded warnings below the results; no "stage" under Done; red no-fly zones with a legend', async () => {
  // both UAVs take off in the middle of the field: one takes off inside the other's region, which
  // every export format warns about
  const doc = smallField('ops warnings');
  const mid = doc.area.coordinates[0][0].map((v, i) => (v + doc.area.coordinates[0][2][i]) / 2);
  doc.uavs = [
    { id: 'A', start: mid, speed_mps: 8 },
    { id: 'B', start: [mid[0] + 0.0001, mid[1]], speed_mps: 8 },
  ];
  doc.no_fly_zones = [{ type: 'Polygon', coordinates: [[[22.9510, 40.6003], [22.9514, 40.6003], [22.9514, 40.6006], [22.9510, 40.6006], [22.9510, 40.6003]]] }];
  const m = await post('/missions', doc);
  const p = await page({ width: 1440, height: 900 });
  await openMission(p, m.id, 'plan');
  await p.click('[data-testid=plan-start]');
  await p.waitForSelector('[data-testid=plan-state][data-state=done]', { timeout: 90000 });
  const planId = Number(await p.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
  const job = await server.api(`/plans/${planId}`);
  const raw = job.warnings;
  assert.ok(raw.length > 0, 'the plan has warnings');
  const items = await p.locator('[data-testid=plan-warning]').evaluateAll((ls) => ls.map((l) => ({ text: l.firstChild.textContent, count: Number(l.dataset.count) })));
  assert.equal(items.length, new Set(items.map((i) => i.text)).size, 'no warning listed twice');
  assert.equal(items.reduce((n, i) => n + i.count, 0), raw.length, 'every warning counted');
  // the server removes repeats of one job's warnings; where any are left, the app groups them
  if (raw.length > new Set(raw).size) assert.ok(items.some((i) => i.count > 1));
  for (const i of items) assert.doesNotMatch(i.text, /\d+\.\d{3,}/, 'numbers rounded for people');
  // below the results: the warnings section comes after the metrics
  const yWarn = (await p.locator('[data-testid=plan-warnings-section]').boundingBox()).y;
  const yMetrics = (await p.locator('[data-testid=metrics-section]').boundingBox()).y;
  assert.ok(yWarn > yMetrics, `warnings (${yWarn}) below the metrics (${yMetrics})`);
  // a finished job shows no stage any more
  assert.equal((await p.locator('.plan-job-stage').first().innerText()).trim(), '');
  // the no-fly zone in the Define tab's red, named in the legend
  await p.waitForSelector('[data-testid=plan-zone-legend] [data-testid=legend-nfz]');
  await h.planDrawn(p);
  const red = await p.evaluate(() => {
    let n = 0;
    for (const c of document.querySelectorAll('#map .plan-tiles canvas')) {
      if (!c.width) continue;
      const s = document.createElement('canvas');
      s.width = c.width;
      s.height = c.height;
      const x = s.getContext('2d');
      x.drawImage(c, 0, 0);
      const d = x.getImageData(0, 0, c.width, c.height).data;
      for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 200 && Math.abs(d[i] - 0xb3) < 14 && Math.abs(d[i + 1] - 0x1a) < 14 && Math.abs(d[i + 2] - 0x1a) < 14) n++;
    }
    return n;
  });
  assert.ok(red > 20, `the no-fly zone's outline is red in the Plan tab (${red} pixels)`);
  await h.shot(p, 'ops-6-warnings');
});

test('defect 7: zero shares cannot be set; the row says why, by its label', async () => {
  const doc = smallField('ops shares');
  doc.uavs.push({ id: 'C', start: doc.uavs[0].start, speed_mps: 8 });
  const m = await post('/missions', doc);
  const p = await page();
  await openMission(p, m.id);
  await p.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length === 3);
  const rows = p.locator('[data-testid=uav-row]');
  const shares = () => rows.locator('[data-testid=uav-share]').evaluateAll((is) => is.map((i) => Number(i.value)));
  for (let i = 0; i < 3; i++) {
    await rows.nth(i).locator('[data-testid=uav-share]').fill('0');
    await rows.nth(i).locator('[data-testid=uav-share]').press('Tab');
    const s = await shares();
    assert.equal(s.reduce((a, b) => a + b, 0), 100, `${s}`);
    assert.ok(s.every((x) => x >= 1), `no share at 0 after typing 0 into row ${i + 1}: ${s}`);
    const note = rows.nth(i).locator('[data-testid=share-note]');
    await note.waitFor();
    assert.match(await note.innerText(), new RegExp(`^${['A', 'B', 'C'][i]}: 1 %`));
  }
  // the document saved is valid (no 422)
  await p.click('[data-testid=mission-save]');
  await p.waitForFunction(() => /revision 2/.test(document.querySelector('[data-testid=mission-status]')?.textContent));
  assert.equal(await p.locator('[data-testid=field-error]').count(), 0);
  await h.shot(p, 'ops-7-shares');
});

test('defects 8, 9 and 2: the compare table fits its panel, cautions; side by side shows one view on equal maps', async () => {
  const m = await post('/missions', { ...olive, name: 'ops compare' });
  const p = await page({ width: 1440, height: 900 });
  await openMission(p, m.id, 'plan');
  await p.click('[data-testid=compare-section] > summary');
  await p.waitForSelector('[data-testid=compare-planner][data-planner=spiral]');
  for (const cb of await p.locator('[data-testid=compare-planner]').all()) {
    const name = await cb.getAttribute('data-planner');
    await cb.setChecked(['darp', 'boustrophedon', 'spiral'].includes(name));
  }
  await p.click('[data-testid=compare-start]');
  await p.waitForSelector('[data-testid=compare-table]', { timeout: 180000 });
  const fit = await p.locator('[data-testid=compare-table]').evaluate((t) => ({ table: t.scrollWidth, panel: t.closest('.plan-section-body').clientWidth }));
  assert.ok(fit.table <= fit.panel, `the table (${fit.table} px) fits its panel (${fit.panel} px)`);
  const headers = await p.locator('[data-testid=compare-table] th').evaluateAll((ts) => ts.map((t) => ({ text: t.textContent, w: t.scrollWidth, cw: t.clientWidth })));
  for (const th of headers) assert.ok(th.w <= th.cw + 1, `header "${th.text}" is not cut`);
  // cautions: one for each planner at least twice the shortest length, from the server's numbers
  const compId = (await server.api(`/missions/${m.id}/comparisons`)).items[0].id;
  const rows = (await server.api(`/comparisons/${compId}`)).result.planners;
  const lengths = rows.filter((r) => r.length_m > 0).map((r) => [r.planner, r.length_m]);
  const best = Math.min(...lengths.map(([, l]) => l));
  const far = lengths.filter(([, l]) => l >= 2 * best).map(([n]) => n).sort();
  const shown = (await p.locator('[data-testid=compare-caution]').evaluateAll((ls) => ls.map((l) => l.dataset.planner))).sort();
  assert.deepEqual(shown, far, `cautions for ${JSON.stringify(lengths)}`);
  await p.locator('[data-testid=compare-table]').scrollIntoViewIfNeeded();
  await h.shot(p, 'ops-8-compare-table');

  await p.waitForSelector('[data-testid=compare-side-by-side]:not([disabled])', { timeout: 180000 });
  await p.click('[data-testid=compare-side-by-side]');
  const maps = p.locator('[data-testid=compare-maps] .plan-overlay-map');
  await p.waitForFunction(() => document.querySelectorAll('[data-testid=compare-maps] .plan-overlay-map[data-zoom]').length === 3);
  const views = () => maps.evaluateAll((ms) => ms.map((m) => ({ zoom: m.dataset.zoom, center: m.dataset.center, view: m.dataset.view, w: m.clientWidth, h: m.clientHeight, scale: m.querySelector('.leaflet-control-scale-line').textContent })));
  const same = (vs) => vs.every((v) => v.zoom === vs[0].zoom && v.center === vs[0].center && v.scale === vs[0].scale && v.w === vs[0].w && v.h === vs[0].h);
  let v = await views();
  assert.ok(same(v), `one view on equal maps: ${JSON.stringify(v)}`);
  // every plan whole in view on every map
  const [s, w, n, e] = v[0].view.split(',').map(Number);
  const jobs = (await server.api(`/missions/${m.id}/plans?limit=20`)).items.filter((j) => j.state === 'done').slice(0, 3);
  assert.equal(jobs.length, 3);
  for (const j of jobs) {
    const paths = await server.api(`/plans/${j.id}/paths.geojson`);
    for (const f of paths.features) {
      if (f.geometry?.type !== 'LineString') continue;
      for (const q of f.geometry.coordinates) assert.ok(q[1] >= s && q[1] <= n && q[0] >= w && q[0] <= e, `plan #${j.id} in view: ${q} in ${v[0].view}`);
    }
  }
  await h.planDrawn(p, '[data-testid=compare-maps] .plan-overlay-map[data-planner=darp]');
  await h.shot(p, 'ops-2-side-by-side');
  // a pan of one map moves the others; a zoom of another zooms all
  const box = await maps.nth(1).boundingBox();
  await p.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await p.mouse.down();
  await p.mouse.move(box.x + box.width / 2 + 80, box.y + box.height / 2 + 40, { steps: 6 });
  await p.mouse.up();
  await p.waitForFunction((c) => document.querySelector('[data-testid=compare-maps] .plan-overlay-map').dataset.center !== c, v[0].center);
  v = await views();
  assert.ok(same(v), `panned together: ${JSON.stringify(v)}`);
  await maps.nth(2).locator('.leaflet-control-zoom-in').click();
  await p.waitForFunction((z) => document.querySelector('[data-testid=compare-maps] .plan-overlay-map').dataset.zoom !== z, v[0].zoom);
  v = await views();
  assert.ok(same(v), `zoomed together: ${JSON.stringify(v)}`);
  for (const planner of ['darp', 'boustrophedon', 'spiral']) await h.planDrawn(p, `[data-testid=compare-maps] .plan-overlay-map[data-planner=${planner}]`);
  await h.shot(p, 'ops-2-side-by-side-panned');
  await p.keyboard.press('Escape');
});

test('defect 9: KML names, the draw hint, a new mission with one UAV, tabs with arrow keys, errors named as the form names them', async () => {
  const p = await page();
  const bad = [];
  p.on('response', (r) => {
    if (r.status() === 422) bad.push(r.url());
  });
  await p.goto(`${server.base}/?tiles=off`);
  await p.waitForSelector('[data-testid=mission-new]');
  // a KML: its names are kept (the server's importer, docs/import.md: the area Placemark's name names the mission)
  const dir = mkdtempSync(join(tmpdir(), 'uavcover-ops-'));
  const kml = join(dir, 'field.kml');
  writeFileSync(
    kml,
    `<?xml version="1.0" encoding="UTF-8"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document><name>Vineyard east</name><Placemark><name>block 3</name><Polygon><outerBoundaryIs><LinearRing><coordinates>22.95,40.6 22.953,40.6 22.953,40.602 22.95,40.602 22.95,40.6</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark></Document></kml>`,
  );
  await p.setInputFiles('[data-testid=mission-import-input]', kml);
  await p.waitForFunction(() => document.querySelector('[data-testid=mission-name]')?.value === 'block 3');

  // a new mission has a UAV: the first vertex drawn raises no error
  await h.tab(p, 'missions');
  await p.click('[data-testid=mission-new]');
  await p.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length === 1);
  const hint = await p.locator('[data-testid=draw-area]').getAttribute('title');
  assert.doesNotMatch(hint, /Finish/);
  await p.click('[data-testid=draw-area]');
  await p.mouse.click(...(await h.mapPoint(p, 0.4, 0.4)));
  await p.waitForTimeout(700);
  for (const [x, y] of [[0.6, 0.4], [0.6, 0.6], [0.4, 0.6], [0.4, 0.4]]) await p.mouse.click(...(await h.mapPoint(p, x, y)));
  await p.waitForFunction(() => document.querySelector('[data-testid=spacing-value]')?.textContent.endsWith(' m'), null, { timeout: 10000 });
  assert.equal(await p.locator('[data-testid=field-error]').count(), 0);
  assert.deepEqual(bad, [], 'no 422 while drawing a new mission');

  // an error names the field as the form does, the path in its tooltip
  await p.fill('[data-testid=altitude-input]', '-5');
  await p.press('[data-testid=altitude-input]', 'Tab');
  const err = p.locator('[data-testid=field-error]').first();
  await err.waitFor({ timeout: 10000 });
  const text = await err.innerText();
  assert.match(text, /^Altitude: /);
  assert.doesNotMatch(text, /altitude_m|camera\.|\[\d+\]/);
  assert.match(await err.getAttribute('title'), /altitude_m/);

  // the tabs: arrow keys move the selection
  await p.focus('#tabs button[aria-selected=true]');
  const selected = () => p.locator('#tabs button[aria-selected=true]').getAttribute('data-tab');
  assert.equal(await selected(), 'define');
  await p.keyboard.press('ArrowRight');
  assert.equal(await selected(), 'plan');
  assert.ok(await p.locator('.tab-panel[data-tab=plan]').isVisible());
  await p.keyboard.press('ArrowLeft');
  await p.keyboard.press('ArrowLeft');
  assert.equal(await selected(), 'missions');
  await p.keyboard.press('End');
  assert.equal(await selected(), 'fly');
  assert.equal(await p.evaluate(() => document.activeElement?.dataset.tab), 'fly');
});

test('defect 9: the Fly map shows the area and its no-fly zones', async () => {
  const m = await post('/missions', { ...olive, name: 'ops fly zones' });
  await planned(m.id);
  const p = await page();
  await openMission(p, m.id, 'fly');
  await p.waitForFunction(() => Number(document.querySelector('.leaflet-flyZones-pane')?.dataset.nfz) === 2, null, { timeout: 30000 });
  assert.equal(await p.locator('.leaflet-flyZones-pane').getAttribute('data-area'), '1');
  const red = await p.evaluate(() => {
    let n = 0;
    for (const c of document.querySelectorAll('.leaflet-flyZones-pane canvas')) {
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 40 && d[i] > 150 && d[i + 1] < 120 && d[i + 2] < 120) n++;
    }
    return n;
  });
  assert.ok(red > 50, `the no-fly zones are drawn red on the Fly map (${red} pixels)`);
  assert.ok(await p.locator('[data-testid=fly-zone-legend] [data-testid=legend-nfz]').isVisible());
  await h.shot(p, 'ops-9-fly-zones');
});

test('the catalog editor: UAVs and cameras added, edited (errors by the field) and deleted', async () => {
  const p = await page();
  await p.goto(`${server.base}/?tiles=off`);
  await p.click('[data-testid=catalog-section] > summary');
  await p.waitForSelector('[data-testid=catalog-item][data-kind=cameras]');
  // a camera, first with an image width that is not an integer
  await p.click('[data-testid=catalog-add][data-kind=cameras]');
  const form = p.locator('[data-testid=catalog-form]');
  await form.locator('[data-testid=catalog-input][data-field=name]').fill('ops editor cam');
  await form.locator('[data-testid=catalog-input][data-field=image_width_px]').fill('4000.5');
  await p.click('[data-testid=catalog-save]');
  await p.waitForSelector('[data-testid=catalog-error][data-field=image_width_px]');
  assert.match(await p.locator('[data-testid=catalog-error]').innerText(), /^Image width: (?!image_width_px)/);
  await form.locator('[data-testid=catalog-input][data-field=image_width_px]').fill('4000');
  await p.click('[data-testid=catalog-save]');
  await p.waitForSelector('[data-testid=catalog-form]', { state: 'detached' });
  const cam = (await server.api('/cameras')).items.find((c) => c.name === 'ops editor cam');
  assert.ok(cam, 'the camera is in the catalog');
  assert.equal(cam.image_width_px, 4000);
  // a UAV carrying it
  await p.click('[data-testid=catalog-add][data-kind=uavs]');
  await form.locator('[data-testid=catalog-input][data-field=name]').fill('ops editor quad');
  await form.locator('[data-testid=catalog-input][data-field=speed_mps]').fill('11');
  await form.locator('[data-testid=catalog-input][data-field=camera_id]').selectOption(String(cam.id));
  await p.click('[data-testid=catalog-save]');
  await p.waitForSelector('[data-testid=catalog-form]', { state: 'detached' });
  let quad = (await server.api('/uavs')).items.find((u) => u.name === 'ops editor quad');
  assert.equal(quad.speed_mps, 11);
  assert.equal(quad.camera_id, cam.id);
  const item = p.locator(`[data-testid=catalog-item][data-kind=uavs][data-id="${quad.id}"]`);
  assert.match(await item.innerText(), /ops editor cam/);
  // edited: a speed out of range is refused next to the field, then a good one saved
  await item.locator('[data-testid=catalog-edit]').click();
  await form.locator('[data-testid=catalog-input][data-field=speed_mps]').fill('0');
  await p.click('[data-testid=catalog-save]');
  await p.waitForSelector('[data-testid=catalog-error][data-field=speed_mps]');
  await form.locator('[data-testid=catalog-input][data-field=speed_mps]').fill('12.5');
  await p.click('[data-testid=catalog-save]');
  await p.waitForSelector('[data-testid=catalog-form]', { state: 'detached' });
  quad = (await server.api('/uavs')).items.find((u) => u.id === quad.id);
  assert.equal(quad.speed_mps, 12.5);
  // the Define tab offers it at once
  await h.tab(p, 'define');
  await p.waitForFunction((id) => !!document.querySelector(`[data-testid=uav-add-catalog] option[value="${id}"]`), quad.id);
  await h.tab(p, 'missions');
  await h.shot(p, 'ops-catalog-editor');
  // deleted
  await item.locator('[data-testid=catalog-delete]').click();
  await item.locator('[data-testid=catalog-delete-confirm]').click();
  await p.waitForSelector(`[data-testid=catalog-item][data-kind=uavs][data-id="${quad.id}"]`, { state: 'detached' });
  assert.ok(!(await server.api('/uavs')).items.some((u) => u.id === quad.id));
});

test('Define: gimbal pitch, a catalog UAV\'s speed and a UAV\'s own camera', async () => {
  const m = await post('/missions', { ...olive, name: 'ops define camera' });
  const cams = (await server.api('/cameras')).items;
  const p = await page();
  await openMission(p, m.id);
  await p.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row] [data-testid=uav-camera]').length === 3);
  await p.fill('[data-testid=gimbal-input]', '-60');
  await p.press('[data-testid=gimbal-input]', 'Tab');
  await p.locator('[data-testid=uav-row]').nth(1).locator('[data-testid=uav-camera]').selectOption(String(cams[1].id));
  await p.click('[data-testid=mission-save]');
  await p.waitForFunction(() => /revision 2\b/.test(document.querySelector('[data-testid=mission-status]')?.textContent));
  assert.equal(await p.locator('[data-testid=field-error]').count(), 0);
  const r = await server.api(`/missions/${m.id}`);
  assert.equal(r.source.camera.gimbal_pitch_deg, -60);
  assert.equal(r.mission.camera.gimbal_pitch_deg, -60);
  const own = r.mission.uavs[1].camera;
  assert.ok(own, JSON.stringify(r.mission.uavs[1]));
  assert.equal(own.hfov_deg, cams[1].hfov_deg);
  assert.equal(own.altitude_m, olive.camera.altitude_m);
  assert.equal(r.mission.uavs[0].camera, undefined);
  // the mission's altitude changes: the UAV's camera follows (the library wants one altitude)
  await p.fill('[data-testid=altitude-input]', '60');
  await p.press('[data-testid=altitude-input]', 'Tab');
  await p.click('[data-testid=mission-save]');
  await p.waitForFunction(() => /revision 3\b/.test(document.querySelector('[data-testid=mission-status]')?.textContent));
  assert.equal((await server.api(`/missions/${m.id}`)).mission.uavs[1].camera.altitude_m, 60);
  // a catalog UAV's speed: the catalog's unless the mission gives one
  const catalog = p.locator('[data-testid=uav-add-catalog]');
  const first = (await catalog.locator('option').evaluateAll((os) => os.map((o) => o.value).filter((v) => v)))[0];
  await catalog.selectOption(first);
  const row = p.locator('[data-testid=uav-row]').nth(3);
  await row.locator('[data-testid=uav-speed-override]').fill('4');
  await row.locator('[data-testid=uav-speed-override]').press('Tab');
  await p.click('[data-testid=mission-save]');
  await p.waitForFunction(() => /revision 4\b/.test(document.querySelector('[data-testid=mission-status]')?.textContent));
  const r4 = await server.api(`/missions/${m.id}`);
  assert.equal(r4.source.uavs[3].catalog_id, Number(first));
  assert.equal(r4.mission.uavs[3].speed_mps, 4);
  await h.shot(p, 'ops-define-camera');
});

test('screenshots of every tab at 1440x900 and 768x1024', async () => {
  const m = await post('/missions', { ...olive, name: 'ops screenshots' });
  await planned(m.id);
  for (const [w, hgt] of [[1440, 900], [768, 1024]]) {
    const p = await page({ width: w, height: hgt });
    await openMission(p, m.id, 'missions');
    await p.waitForSelector('[data-testid=mission-item]');
    for (const t of ['missions', 'define', 'plan', 'fly']) {
      await h.tab(p, t);
      if (t === 'plan') await h.planDrawn(p);
      if (t === 'define') await p.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length === 3);
      await p.waitForTimeout(300);
      const over = await p.evaluate(() => document.documentElement.scrollWidth - document.documentElement.clientWidth);
      assert.ok(over <= 0, `${t} at ${w}x${hgt}: no sideways overflow (${over} px)`);
      await h.shot(p, `ops-${w}x${hgt}-${t}`);
    }
  }
});

test('no console errors or warnings', () => {
  assert.deepEqual(problems.flat(), []);
});
