// End-to-end flows beyond the nine steps, against the real server (temporary SQLite, tiles
// off, no mocks), screenshots into the same artifacts folder as app.test.mjs:
//   a. the newcomer: open the seeded example from the Missions tab, plan it, see its regions, export
//      one UAV's QGC mission and parse it; reload and see the latest plan again; pick an earlier plan;
//   b. the keyboard while drawing (Ctrl-Z, Esc) and Delete of a selected vertex or no-fly zone;
//   a2. the plan's tiles drawn in the drawing worker, and in the page without OffscreenCanvas;
//   c. a tablet-sized screen (768x1024): every tab usable, no horizontal overflow.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { after, before, test } from 'node:test';
import * as h from './harness.mjs';

let server, browser;
const problems = [];
const flow = { missionId: null, plans: [] };

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

/**
 * Pixels of the map's canvases close to an RGB colour (the plan is drawn on canvas tiles, each holding
 * a bitmap from the drawing worker: copied to a scratch canvas to be read).
 */
async function colouredPixels(page, hex) {
  await h.planDrawn(page);
  return page.evaluate((hex) => {
    const [r, g, b] = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
    let n = 0;
    for (const c of document.querySelectorAll('#map canvas')) {
      if (!c.width || !c.height) continue;
      const scratch = document.createElement('canvas');
      scratch.width = c.width;
      scratch.height = c.height;
      const ctx = scratch.getContext('2d');
      ctx.drawImage(c, 0, 0);
      const d = ctx.getImageData(0, 0, c.width, c.height).data;
      for (let i = 0; i < d.length; i += 4)
        if (d[i + 3] > 200 && Math.abs(d[i] - r) < 12 && Math.abs(d[i + 1] - g) < 12 && Math.abs(d[i + 2] - b) < 12) n++;
    }
    return n;
  }, hex);
}

async function planAndWait(p) {
  await p.click('[data-testid=plan-start]');
  await p.waitForSelector('[data-testid=plan-state][data-state=done]', { timeout: 90000 });
  await p.waitForFunction(() => {
    const m = document.querySelector('[data-testid=metrics-panel]');
    const s = document.querySelector('[data-testid=plan-state]');
    return m && s && m.closest('.plan-results:not([hidden])');
  });
  return Number(await p.locator('[data-testid=metrics-panel]').getAttribute('data-plan-id'));
}

test('a. newcomer: open the seeded example, plan, export QGC; reload shows the latest plan', async () => {
  const p = await page();
  await p.goto(`${server.base}/?tiles=off`);
  const item = p.locator('[data-testid=mission-item]').filter({ hasText: 'North olive grove' });
  await item.waitFor();
  flow.missionId = Number(await item.getAttribute('data-id'));
  await item.locator('[data-testid=mission-open]').click();
  await p.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length > 0);
  const seeded = (await server.api(`/missions/${flow.missionId}`)).mission;
  await h.tab(p, 'plan');
  assert.match(await p.locator('[data-testid=plan-mission]').innerText(), /North olive grove/);
  assert.ok(await p.locator('[data-testid=plan-history]').isHidden(), 'no plans yet: no plan list');

  const first = await planAndWait(p);
  const items = p.locator('[data-testid=plan-legend-item]');
  assert.equal(await items.count(), seeded.uavs.length);
  for (let i = 0; i < seeded.uavs.length; i++) {
    assert.ok(Number(await items.nth(i).getAttribute('data-regions')) >= 1, 'each UAV has a region');
    assert.ok(Number(await items.nth(i).getAttribute('data-paths')) >= 1, 'each UAV has a path');
  }
  const colour = await items.first().locator('.plan-swatch').evaluate((e) => {
    const [r, g, b] = getComputedStyle(e).backgroundColor.match(/\d+/g).map(Number);
    return '#' + [r, g, b].map((x) => x.toString(16).padStart(2, '0')).join('');
  });
  assert.ok((await colouredPixels(p, colour)) > 200, 'the first UAV is drawn in its colour');
  await h.shot(p, 'flow-a1-planned');

  // one UAV's QGC mission, parsed
  const job = await server.api(`/plans/${first}`);
  const uav = job.result.uavs[0].id;
  const [download] = await Promise.all([p.waitForEvent('download'), p.click(`[data-testid=export-qgc][data-uav="${uav}"]`)]);
  const qgc = JSON.parse(readFileSync(await download.path(), 'utf8'));
  assert.equal(qgc.fileType, 'Plan');
  assert.ok(qgc.mission.items.length > 2);
  const waypoints = qgc.mission.items.filter((it) => it.command === 16);
  assert.ok(waypoints.length > 0, 'NAV_WAYPOINT items');
  for (const w of waypoints) {
    const [lat, lon] = w.params.slice(4, 6);
    assert.ok(Math.abs(lat - seeded.uavs[0].start[1]) < 0.05 && Math.abs(lon - seeded.uavs[0].start[0]) < 0.05, 'waypoints near the field');
  }

  // a second plan with another planner: the list holds both, newest first
  await p.selectOption('[data-testid=plan-planner]', 'boustrophedon');
  const second = await planAndWait(p);
  assert.notEqual(second, first);
  await p.waitForFunction((n) => document.querySelectorAll('[data-testid=plan-history] option[value]:not([value=""])').length === n, 2);
  const listed = await p.locator('[data-testid=plan-history] option').evaluateAll((os) => os.map((o) => o.value).filter((v) => v));
  assert.deepEqual(listed.map(Number), [second, first]);
  flow.plans = [second, first];

  // reload: the same mission, the Plan tab, the latest plan drawn again
  await p.reload();
  assert.match(p.url(), new RegExp(`[?&]mission=${flow.missionId}\\b.*#plan$`));
  await p.waitForSelector(`[data-testid=metrics-panel][data-plan-id="${second}"]`, { timeout: 20000 });
  assert.equal(await p.locator('[data-testid=plan-legend-item]').count(), seeded.uavs.length);
  assert.equal(await p.locator('[data-testid=plan-history]').inputValue(), String(second));
  await p.waitForFunction(() => document.querySelectorAll('#map canvas').length > 0);
  assert.ok((await colouredPixels(p, colour)) > 200, 'the reloaded plan is drawn');
  assert.equal(Number(await p.locator('[data-testid=metric-poc]').getAttribute('data-value')), (await server.api(`/plans/${second}`)).metrics.poc);
  // the seeded example flies a camera: the metrics show plan.json's image estimate (issue 18)
  assert.ok(seeded.camera, 'the seeded example has a camera block');
  const planJson = await server.api(`/plans/${second}/plan.json`);
  assert.ok(planJson.images.images > 0);
  assert.equal(await p.locator('[data-testid=images-images]').textContent(), String(planJson.images.images));
  await h.shot(p, 'flow-a2-reloaded');

  // pick the earlier plan from the list
  await p.selectOption('[data-testid=plan-history]', String(first));
  await p.waitForSelector(`[data-testid=metrics-panel][data-plan-id="${first}"]`);
  assert.equal(Number(await p.locator('[data-testid=metric-poc]').getAttribute('data-value')), job.metrics.poc);
  await h.shot(p, 'flow-a3-earlier-plan');

  // opening the mission from the Missions tab in a fresh page shows its latest plan too
  const q = await page();
  await q.goto(`${server.base}/?tiles=off`);
  await q.locator(`[data-testid=mission-item][data-id="${flow.missionId}"] [data-testid=mission-open]`).click();
  await h.tab(q, 'plan');
  await q.waitForSelector(`[data-testid=metrics-panel][data-plan-id="${second}"]`, { timeout: 20000 });
  await q.context().close();
  await p.context().close();
});

test('a2. the plan tiles: drawn in the worker, and in the page when the browser has no OffscreenCanvas', async () => {
  assert.ok(flow.missionId && flow.plans.length, 'needs flow a');
  const tileKinds = (p) =>
    p.evaluate(() => [...document.querySelectorAll('#map canvas.plan-tile')].map((c) => (c.getContext('bitmaprenderer') ? 'bitmap' : '2d')));
  for (const withWorker of [true, false]) {
    const p = await page();
    if (!withWorker) await p.addInitScript(() => delete window.OffscreenCanvas);
    await p.goto(`${server.base}/?tiles=off&mission=${flow.missionId}#plan`);
    await p.waitForSelector(`[data-testid=metrics-panel][data-plan-id="${flow.plans[0]}"]`, { timeout: 20000 });
    assert.ok((await colouredPixels(p, '#1f78b5')) > 200, `the first UAV is drawn (${withWorker ? 'worker' : 'page'})`);
    const kinds = await tileKinds(p);
    assert.ok(kinds.length > 0);
    // a tile shown from a worker's bitmap has a bitmaprenderer context; one drawn in the page a 2d one
    if (withWorker) assert.ok(kinds.includes('bitmap'), kinds.join());
    else assert.ok(kinds.every((k) => k === '2d'), kinds.join());
    await h.shot(p, withWorker ? 'flow-a4-tiles-worker' : 'flow-a5-tiles-page');
    await p.context().close();
  }
});

test('b. keyboard: Ctrl-Z and Esc while drawing, Delete a selected vertex or no-fly zone', async () => {
  const p = await page();
  await p.goto(`${server.base}/?tiles=off`);
  await p.waitForSelector('[data-testid=mission-new]');
  await p.click('[data-testid=mission-new]');
  await p.waitForSelector('[data-testid=draw-area]');
  const vertices = p.locator('#map .leaflet-marker-icon.marker-icon:not(.marker-icon-middle)');
  const click = async (fx, fy) => p.mouse.click(...(await h.mapPoint(p, fx, fy)));
  const closedPolygon = async (button, ring) => {
    await p.click(`[data-testid=${button}]`);
    for (const [x, y] of ring) await click(x, y);
    await click(...ring[0]);
    await p.waitForFunction(() => !document.querySelector('#map').classList.contains('define-drawing'));
  };
  await closedPolygon('draw-area', [[0.2, 0.2], [0.8, 0.2], [0.8, 0.8], [0.2, 0.8]]);
  await p.waitForFunction(() => document.querySelectorAll('#map .leaflet-marker-icon.marker-icon:not(.marker-icon-middle)').length === 4);
  await closedPolygon('draw-nfz', [[0.45, 0.45], [0.6, 0.45], [0.6, 0.6], [0.45, 0.6]]);
  await p.waitForFunction(() => document.querySelectorAll('#map .leaflet-marker-icon.marker-icon:not(.marker-icon-middle)').length === 8);

  // drawing a third shape: three vertices, Ctrl-Z takes the last back, Esc cancels the drawing
  const drawingMarkers = () => p.locator('#map .leaflet-marker-pane .marker-icon').count();
  const idle = await drawingMarkers();
  await p.click('[data-testid=draw-nfz]');
  assert.ok(await p.locator('#map').evaluate((m) => m.classList.contains('define-drawing')));
  for (const [x, y] of [[0.25, 0.25], [0.35, 0.25], [0.35, 0.35]]) await click(x, y);
  const drawing = await drawingMarkers();
  assert.ok(drawing >= idle + 3, `three new vertices (${idle} -> ${drawing})`);
  await p.keyboard.press('Control+z');
  assert.equal(await drawingMarkers(), drawing - 1, 'Ctrl-Z removed the last vertex');
  await h.shot(p, 'flow-b1-drawing-after-ctrl-z');
  await p.keyboard.press('Escape');
  await p.waitForFunction(() => !document.querySelector('#map').classList.contains('define-drawing'));
  assert.equal(await drawingMarkers(), idle, 'Esc cancelled the drawing');
  assert.equal(await vertices.count(), 8, 'no shape was added');
  assert.doesNotMatch((await p.locator('[data-testid=draw-nfz]').getAttribute('class')) ?? '', /active/);

  // select the area's first vertex, Delete removes it
  await vertices.first().click();
  await p.keyboard.press('Delete');
  await p.waitForFunction(() => document.querySelectorAll('#map .leaflet-marker-icon.marker-icon:not(.marker-icon-middle)').length === 7);
  // select the no-fly zone by clicking inside it, Delete removes it (its four vertices go)
  await click(0.52, 0.52);
  await p.keyboard.press('Delete');
  await p.waitForFunction(() => document.querySelectorAll('#map .leaflet-marker-icon.marker-icon:not(.marker-icon-middle)').length === 3);
  await h.shot(p, 'flow-b2-deleted-vertex-and-nfz');
  // Ctrl-Z brings the zone back
  await p.keyboard.press('Control+z');
  await p.waitForFunction(() => document.querySelectorAll('#map .leaflet-marker-icon.marker-icon:not(.marker-icon-middle)').length === 7);
  await p.context().close();
});

test('c. tablet size (768x1024): every tab usable, nothing overflows sideways', async () => {
  const p = await page({ width: 768, height: 1024 });
  const id = flow.missionId ?? (await server.api('/missions?name=olive')).items[0].id;
  await p.goto(`${server.base}/?tiles=off`);
  await p.locator(`[data-testid=mission-item][data-id="${id}"]`).waitFor();
  for (const name of ['missions', 'define', 'plan', 'fly']) {
    if (name === 'define') {
      await h.tab(p, 'missions');
      await p.locator(`[data-testid=mission-item][data-id="${id}"] [data-testid=mission-open]`).click();
      await p.waitForFunction(() => document.querySelectorAll('[data-testid=uav-row]').length > 0);
    }
    await h.tab(p, name);
    if (name === 'plan' && flow.plans.length) await p.waitForSelector('[data-testid=metrics-panel]', { timeout: 20000 });
    await p.waitForTimeout(200);
    const layout = await p.evaluate(() => {
      const doc = document.documentElement;
      const panel = document.querySelector(`.tab-panel:not([hidden])`);
      const off = [];
      for (const b of [...document.querySelectorAll('#tabs button'), ...panel.querySelectorAll('button, select, input:not([type=file])')]) {
        const r = b.getBoundingClientRect();
        if (r.width === 0 && r.height === 0) continue; // not shown (collapsed section, hidden row)
        if (r.left < 0 || r.right > window.innerWidth + 0.5) off.push(`${b.tagName} ${b.dataset.testid ?? b.textContent.trim().slice(0, 20)} [${r.left.toFixed(0)}, ${r.right.toFixed(0)}]`);
      }
      return { scrollWidth: doc.scrollWidth, clientWidth: doc.clientWidth, bodyScroll: document.body.scrollWidth, panelOverflow: panel.parentElement.scrollWidth - panel.parentElement.clientWidth, off };
    });
    assert.ok(layout.scrollWidth <= layout.clientWidth, `${name}: the page scrolls sideways (${layout.scrollWidth} > ${layout.clientWidth})`);
    assert.ok(layout.panelOverflow <= 0, `${name}: the panel scrolls sideways by ${layout.panelOverflow}px`);
    assert.deepEqual(layout.off, [], `${name}: controls outside the screen`);
    // the tab's first button can be clicked (not covered by the map)
    const firstButton = p.locator(`.tab-panel:not([hidden]) button:visible`).first();
    if (await firstButton.count()) await firstButton.click({ trial: true });
    await h.shot(p, `tablet-${name}`);
  }
  await p.context().close();
});

test('no console errors or warnings in these flows', () => {
  assert.deepEqual(problems.flat(), []);
});
